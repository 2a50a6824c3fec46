"""dxl_probe.py CASE PATH BAUD [ARGS]: a controller's uses of a Dynamixel
bus on a tty, each timed in virtual time, for tests/process/test_serial.py.
It prints key=value pairs: spans in ns of time.monotonic_ns() and, as
NAME_cpu, the process CPU spent within each (in cpu mode the span may be
late by that much), replies as hex.

  roundtrip PATH BAUD [DELAY]  PING and READ of Present Position from id 1;
                               with DELAY, Return Delay Time (9) written first
  vtime PATH BAUD              VMIN/VTIME and O_NONBLOCK reads
  spin PATH BAUD               an O_NONBLOCK read spun on until a reply or a
                               CLOCK_REALTIME timeout, as the Dynamixel SDK does
  drain PATH BAUD              tcdrain and FIONREAD around a READ
  faults PATH BAUD             a bad CRC, an unknown id, the tty at another baud
  move PATH BAUD GOAL STATE    torque on, Goal Position GOAL; Present Position
                               read until within 40 counts; the angle from STATE
"""

import errno
import fcntl
import os
import struct
import sys
import termios
import time

import dxl_bus as bus

PRESENT = bus.read_packet(1, bus.PRESENT_POSITION, 4)
PRESENT_REPLY = bus.status_len(4)


def out(**kv):
    print(" ".join("%s=%s" % item for item in kv.items()), flush=True)


def exchange(fd, baud, name, pkt, n):
    """pkt written, then one read that waits for the n bytes of the reply
    (VMIN n): the span from before the write to after the read."""
    bus.set_line(fd, baud, n, 0)
    bus.settle()
    t0, c0 = bus.now()
    os.write(fd, pkt)
    raw = os.read(fd, n)
    t1, c1 = bus.now()
    out(**{name + "_ns": t1 - t0, name + "_cpu": c1 - c0, name + "_reply": raw.hex()})
    return raw


def roundtrip(path, baud, delay=None):
    fd = bus.open_line(path, baud)
    exchange(fd, baud, "warmup", bus.packet(1, bus.PING), bus.status_len(3))  # (Python's first calls cost most)
    if delay is not None:
        raw = exchange(fd, baud, "delay_write", bus.write_packet(1, bus.RETURN_DELAY_TIME, bytes([int(delay)])),
                       bus.status_len(0))
        out(delay_write_error=bus.parse_status(raw)[1])
    exchange(fd, baud, "ping", bus.packet(1, bus.PING), bus.status_len(3))
    raw = exchange(fd, baud, "read", PRESENT, PRESENT_REPLY)
    s = bus.parse_status(raw)
    out(read_error=s[1], position=int.from_bytes(s[2], "little", signed=True))


def timed_read(fd, name, n=100):
    """One read, from just before it to just after."""
    t0, c0 = bus.now()
    try:
        got = os.read(fd, n)
        result = len(got)
    except BlockingIOError as e:
        got, result = b"", errno.errorcode[e.errno]
    t1, c1 = bus.now()
    out(**{name + "_result": result, name + "_ns": t1 - t0, name + "_cpu": c1 - c0})
    return got


def vtime(path, baud):
    fd = bus.open_line(path, baud, 0, 0)
    bus.settle()
    timed_read(fd, "vmin0_vtime0")                         # nothing has come: b"" at once
    flags = fcntl.fcntl(fd, fcntl.F_GETFL)
    fcntl.fcntl(fd, fcntl.F_SETFL, flags | os.O_NONBLOCK)
    bus.settle()
    timed_read(fd, "nonblock")                             # EAGAIN at once
    fcntl.fcntl(fd, fcntl.F_SETFL, flags)
    bus.set_line(fd, baud, 0, 2)
    os.write(fd, bus.packet(7, bus.PING))                  # no servo 7: no answer
    bus.settle()
    timed_read(fd, "vtime2_silent")                        # b"" after 2 tenths
    bus.settle()
    t0, c0 = bus.now()                                     # an answer ends the wait at its first byte
    os.write(fd, PRESENT)
    got = os.read(fd, 100)
    t1, c1 = bus.now()
    out(vtime2_first_result=len(got), vtime2_first_ns=t1 - t0, vtime2_first_cpu=c1 - c0)
    bus.set_line(fd, baud, PRESENT_REPLY, 0)               # the rest of that reply
    got += os.read(fd, PRESENT_REPLY - len(got))
    out(vtime2_first_whole=int(bus.parse_status(got) is not None))
    bus.set_line(fd, baud, 5, 0)
    bus.settle()
    t0, c0 = bus.now()                                     # VMIN 5: the first 5 bytes of the 15
    os.write(fd, PRESENT)
    got = os.read(fd, 100)
    t1, c1 = bus.now()
    out(vmin5_result=len(got), vmin5_ns=t1 - t0, vmin5_cpu=c1 - c0)
    bus.set_line(fd, baud, PRESENT_REPLY - len(got), 0)
    got += os.read(fd, 100)
    t2, c2 = bus.now()
    out(vmin_rest_ns=t2 - t0, vmin_rest_cpu=c2 - c0, vmin_whole=int(bus.parse_status(got) is not None))


def spin(path, baud):
    """The SDK's rxPacket: a non-blocking read tried again and again, the
    timeout checked on CLOCK_REALTIME (its getCurrentTime)."""
    fd = bus.open_line(path, baud)
    fcntl.fcntl(fd, fcntl.F_SETFL, fcntl.fcntl(fd, fcntl.F_GETFL) | os.O_NONBLOCK)
    for name, pkt, n in (("reply", PRESENT, PRESENT_REPLY), ("silent", bus.packet(7, bus.PING), 14)):
        bus.settle()
        t0, c0 = bus.now()
        os.write(fd, pkt)
        start = time.time_ns()
        got, tries = b"", 0
        while len(got) < n:
            try:
                got += os.read(fd, n - len(got))
            except BlockingIOError:
                tries += 1
            if time.time_ns() - start > 50 * 1000000:    # 50 ms: the packet's timeout
                break
        t1, c1 = bus.now()
        out(**{name + "_ns": t1 - t0, name + "_cpu": c1 - c0, name + "_len": len(got), name + "_tries": tries})


def drain(path, baud):
    fd = bus.open_line(path, baud, 0, 0)
    bus.settle()
    t0, c0 = bus.now()
    os.write(fd, PRESENT)
    termios.tcdrain(fd)
    t1, c1 = bus.now()
    out(drain_ns=t1 - t0, drain_cpu=c1 - c0, after_drain=fionread(fd))
    # Samples while the reply comes in: how much has arrived by when.
    for i in range(12):
        time.sleep(0.0002)
        ta, _ = bus.now()
        n = fionread(fd)
        tb, _ = bus.now()
        out(**{"sample%d_from" % i: ta - t0, "sample%d_to" % i: tb - t0, "sample%d_count" % i: n})
    bus.set_line(fd, baud, PRESENT_REPLY, 0)
    got = os.read(fd, 100)
    out(read_len=len(got), after_read=fionread(fd))


def fionread(fd):
    return struct.unpack("i", fcntl.ioctl(fd, termios.FIONREAD, b"\0\0\0\0"))[0]


def faults(path, baud):
    fd = bus.open_line(path, baud, 0, 1)                   # reads end 0.1 s after silence
    bad = bytearray(PRESENT)
    bad[-1] ^= 0x5A
    os.write(fd, bytes(bad))
    got = bus.read_upto(fd, 100)
    s = bus.parse_status(got)
    out(bad_crc_reply=got.hex() or "none", bad_crc_error=s[1] if s else "none", bad_crc_id=s[0] if s else "none")
    os.write(fd, bus.packet(7, bus.PING))
    out(unknown_id_len=len(bus.read_upto(fd, 100)))
    other = 115200 if baud != 115200 else 57600
    bus.set_line(fd, other, 0, 1)
    os.write(fd, bus.packet(1, bus.PING))
    out(other_baud_len=len(bus.read_upto(fd, 100)))
    bus.set_line(fd, baud, 0, 1)
    os.write(fd, bus.packet(1, bus.PING))
    got = bus.read_upto(fd, 100)
    s = bus.parse_status(got)
    out(back_len=len(got), back_error=s[1] if s else "none")


def move(path, baud, goal, state):
    fd = bus.open_line(path, baud, 0, 1)

    def transact(pkt, n):
        os.write(fd, pkt)
        s = bus.parse_status(bus.read_upto(fd, n))
        if s is None or s[1]:
            raise SystemExit("dxl_probe: bad status %r for %s" % (s, pkt.hex()))
        return s[2]

    def present():
        return int.from_bytes(transact(PRESENT, PRESENT_REPLY), "little", signed=True)

    start = present()
    transact(bus.write_packet(1, bus.TORQUE_ENABLE, b"\x01"), bus.status_len(0))
    t0 = time.monotonic_ns()
    transact(bus.write_packet(1, bus.GOAL_POSITION, goal.to_bytes(4, "little", signed=True)), bus.status_len(0))
    pos, farthest = start, 0
    while abs(pos - goal) > 40 and time.monotonic_ns() - t0 < 3 * 10**9:  # (3.5 degrees)
        time.sleep(0.01)
        pos = present()
        farthest = max(farthest, abs(pos - start))
    reached = time.monotonic_ns() - t0
    time.sleep(0.5)                                        # and it stays there
    held = present()
    with open(state) as f:                                 # the simulated joint, read beside the servo
        angle = float(f.readline().split()[0])
    out(start=start, goal=goal, reached_ns=reached, position=pos, held=held, angle=angle)


def main():
    case, path, baud = sys.argv[1], sys.argv[2], int(sys.argv[3])
    rest = sys.argv[4:]
    if case == "roundtrip":
        roundtrip(path, baud, *rest)
    elif case == "move":
        move(path, baud, int(rest[0]), rest[1])
    else:
        {"vtime": vtime, "spin": spin, "drain": drain, "faults": faults}[case](path, baud)


if __name__ == "__main__":
    main()
