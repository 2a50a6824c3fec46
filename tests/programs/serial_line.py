"""serial_line.py CASE PATH: what a program may ask of a tty beyond reads and
writes, for tests/process/test_serial_line.py (a line at 1 Mbit/s with a
Dynamixel servo, id 1). Prints key=value pairs; spans in ns of the virtual
CLOCK_MONOTONIC (run it in lockstep with --no-slack: each span then starts
at a time the program slept to).

  bother PATH   the rate set with TCSETS2 and BOTHER (c_ospeed): a PING
                at 57600 unanswered, at 1 Mbit/s answered; TCGETS2 reads
                the rate back; tcdrain after 100 bytes at 1 Mbit/s, at
                250000 and at 1234567 (no termios code for either)
  flush PATH    tcflush TCOFLUSH, TCIFLUSH, TCIOFLUSH on a reply that has
                arrived, TCIFLUSH in the middle of one, a bad queue
  modem PATH    TIOCMGET after open, after TIOCMBIC and TIOCMBIS
  twofds PATH   two fds open on the line: each reads the whole reply
"""

import ctypes
import errno
import fcntl
import os
import struct
import sys
import termios
import time

import dxl_bus as bus

# struct termios2 (asm-generic/termbits.h): four flags, c_line, c_cc[19],
# c_ispeed, c_ospeed; its ioctls are _IOR/_IOW('T', 0x2A/0x2B, 44 bytes).
TERMIOS2 = "=IIIIB19sII"
TCGETS2, TCSETS2 = 0x802C542A, 0x402C542B
BOTHER, CBAUD = 0o010000, 0o010017
PING = bus.packet(1, bus.PING)
PING_REPLY = bus.status_len(3)

libc = ctypes.CDLL(None, use_errno=True)


class Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


def sleep_until(t_ns):
    """Until an absolute CLOCK_MONOTONIC time: what follows happens then."""
    ts = Timespec(t_ns // 10**9, t_ns % 10**9)
    while libc.clock_nanosleep(time.CLOCK_MONOTONIC, 1, ctypes.byref(ts), None) == errno.EINTR:
        pass


def next_ms():
    """A whole millisecond ahead: a span's start, slept to."""
    t = (time.monotonic_ns() // 10**6 + 2) * 10**6
    sleep_until(t)
    return t


def out(**kv):
    print(" ".join("%s=%s" % item for item in kv.items()), flush=True)


def get2(fd):
    return list(struct.unpack(TERMIOS2, fcntl.ioctl(fd, TCGETS2, bytes(struct.calcsize(TERMIOS2)))))


def set_rate(fd, rate, vmin, vtime=0):
    """Raw 8N1 at any rate: CBAUD's bits BOTHER, the rate in c_ispeed and
    c_ospeed (what pyserial does for a rate without a code)."""
    t = get2(fd)
    t[0] = t[1] = t[3] = 0
    t[2] = (t[2] & ~CBAUD) | BOTHER | termios.CS8 | termios.CREAD | termios.CLOCAL
    cc = bytearray(t[5])
    cc[termios.VMIN], cc[termios.VTIME] = vmin, vtime
    t[5] = bytes(cc)
    t[6] = t[7] = rate
    fcntl.ioctl(fd, TCSETS2, struct.pack(TERMIOS2, *t))


def drain_span(fd, n):
    """n bytes written, tcdrain: from the write to the drain's return."""
    t0 = next_ms()
    os.write(fd, bytes(n))  # zeros: no packet, the servo ignores them
    termios.tcdrain(fd)
    return time.monotonic_ns() - t0


def bother(path):
    fd = bus.open_line(path, 57600, 0, 1)
    os.write(fd, PING)
    out(at_57600=len(bus.read_upto(fd, PING_REPLY)))  # VTIME 0.1 s: nothing came
    set_rate(fd, 1000000, PING_REPLY)
    t = get2(fd)
    out(cbaud=oct(t[2] & CBAUD), ispeed=t[6], ospeed=t[7])
    t0 = next_ms()
    os.write(fd, PING)
    raw = os.read(fd, PING_REPLY)
    out(ping_ns=time.monotonic_ns() - t0, ping_reply=raw.hex())
    out(drain_1000000_ns=drain_span(fd, 100))
    for rate, n in ((250000, 100), (1234567, 100)):
        set_rate(fd, rate, 1)
        out(**{"drain_%d_ns" % rate: drain_span(fd, n), "ospeed_%d" % rate: get2(fd)[7]})


def waiting(fd):
    return struct.unpack("i", fcntl.ioctl(fd, termios.FIONREAD, bytes(4)))[0]


def flush(path):
    fd = bus.open_line(path, 1000000, 0, 0)
    for queue in ("TCOFLUSH", "TCIFLUSH", "TCIOFLUSH"):
        t0 = next_ms()
        os.write(fd, PING)
        sleep_until(t0 + 2 * 10**6)  # the whole reply has arrived
        before = waiting(fd)
        termios.tcflush(fd, getattr(termios, queue))
        after = waiting(fd)
        rest = bus.read_upto(fd, 100)  # VMIN 0, VTIME 0: what is there
        out(**{queue + "_before": before, queue + "_after": after, queue + "_read": rest.hex() or "-"})
    # In the middle of a reply: the bytes arrived go, those still on the
    # wire come.
    mid = int(sys.argv[3])
    bus.set_line(fd, 1000000, PING_REPLY, 0)
    t0 = next_ms()
    os.write(fd, PING)
    sleep_until(t0 + mid)
    termios.tcflush(fd, termios.TCIFLUSH)
    bus.set_line(fd, 1000000, 0, 1)
    rest = bus.read_upto(fd, PING_REPLY)  # until 0.1 s without a byte
    out(mid_read=rest.hex() or "-")
    try:
        termios.tcflush(fd, 99)
        out(bad_queue="accepted")
    except termios.error as e:
        out(bad_queue=errno.errorcode[e.args[0]])


def modem(path):
    fd = bus.open_line(path, 1000000)
    get = lambda: struct.unpack("i", fcntl.ioctl(fd, termios.TIOCMGET, bytes(4)))[0]
    lines = termios.TIOCM_DTR | termios.TIOCM_RTS
    opened = get()
    fcntl.ioctl(fd, termios.TIOCMBIC, struct.pack("i", lines))
    cleared = get()
    fcntl.ioctl(fd, termios.TIOCMBIS, struct.pack("i", termios.TIOCM_RTS))
    rts = get()
    out(opened=opened & lines, cleared=cleared & lines, rts=rts & lines)


def twofds(path):
    a = bus.open_line(path, 1000000, PING_REPLY, 0)
    b = bus.open_line(path, 1000000, PING_REPLY, 0)
    t0 = next_ms()
    os.write(a, PING)
    got_a = os.read(a, PING_REPLY)
    t_a = time.monotonic_ns() - t0
    got_b = os.read(b, PING_REPLY)
    t_b = time.monotonic_ns() - t0
    out(a=got_a.hex(), b=got_b.hex(), a_ns=t_a, b_ns=t_b, a_left=waiting(a), b_left=waiting(b))


if __name__ == "__main__":
    {"bother": bother, "flush": flush, "modem": modem, "twofds": twofds}[sys.argv[1]](sys.argv[2])
