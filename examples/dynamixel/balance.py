#!/usr/bin/env python3
"""balance.py: keep an inverted pendulum upright through a ROBOTIS Dynamixel
X-series servo (an XM430-W350) on a serial line, as a plain Python program
that knows nothing of tcs: Protocol 2.0 packets of its own over a tty in raw
mode (os and termios; no SDK), a loop paced by clock_nanosleep on absolute
deadlines. On the bench the tty would be the servo's USB adapter (a U2D2).

Each cycle: one READ of Present Velocity (128) and Present Position (132),
8 bytes from 128; a PD law about upright; one WRITE of Goal Current (102).
The servo runs in Current Control Mode (Operating Mode 0): the torque is
the current times the motor's torque constant. Angle 0 hangs down, pi is
up (Present Position 2048 is hanging, +1 count is +2pi/4096 rad).

  balance.py [--port PATH] [--baud B] [--id N] [--rate HZ] [--seconds S]
             [--work-ms MS] [--kp N*m/rad] [--kd N*m*s/rad]

--work-ms MS burns MS milliseconds of the CPU this program runs on every
cycle, by its own CPU clock, standing for a heavier control law: on the
robot's computer that clock counts that computer's time. At the end it
prints how it did: cycles, rate, deadline misses, the bus's time a cycle
and the largest distance from upright over its last 2 seconds, with
BALANCED (under 0.1 rad) or FELL.
"""

import argparse
import ctypes
import errno
import math
import os
import select
import signal
import sys
import termios
import time

# ---- Protocol 2.0 (ROBOTIS e-Manual, "Protocol 2.0") -------------------------

READ, WRITE = 0x02, 0x03
PRESENT_VELOCITY, GOAL_CURRENT, TORQUE_ENABLE, OPERATING_MODE = 128, 102, 64, 11
CURRENT_MODE = 0
STATUS_OVERHEAD = 11  # header 4, id, length 2, 0x55, error, CRC 2

# XM430-W350: 4.1 N*m at its stall current, 2.3 A (e-Manual); Goal Current
# in units of 2.69 mA; Present Velocity in 0.229 rpm. Goal Current is kept
# within the stall current (855 units): more is what 12 V cannot drive
# through the motor at rest, and would only make the law's output lie.
TORQUE_PER_AMP = 4.1 / 2.3
CURRENT_UNIT = 2.69e-3
MAX_CURRENT = 855
VELOCITY_UNIT = 0.229 * 2 * math.pi / 60
COUNTS_PER_RAD = 4096 / (2 * math.pi)


def crc16(data):
    """The e-Manual's CRC-16: polynomial 0x8005, MSB first, initial 0."""
    crc = 0
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def stuff(data):
    """Byte stuffing: FF FF FD inside a packet's instruction and params
    gets an FD after it, so that it cannot be taken for a header."""
    return data.replace(b"\xff\xff\xfd", b"\xff\xff\xfd\xfd")


def unstuff(data):
    return data.replace(b"\xff\xff\xfd\xfd", b"\xff\xff\xfd")


def instruction(dxl_id, ins, params):
    """Header FF FF FD 00, id, length (what follows it: instruction and
    params, stuffed, and the CRC), then the CRC of all that goes before."""
    payload = stuff(bytes([ins]) + params)
    body = bytes([0xFF, 0xFF, 0xFD, 0x00, dxl_id]) + (len(payload) + 2).to_bytes(2, "little") + payload
    return body + crc16(body).to_bytes(2, "little")


class BusError(Exception):
    pass


class Servo:
    """One servo on a tty in raw mode at the servo's baud."""

    def __init__(self, path, baud, dxl_id):
        speed = getattr(termios, "B%d" % baud, None)
        if speed is None:
            raise BusError("no termios speed for %d baud" % baud)
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
        self.id = dxl_id
        a = termios.tcgetattr(self.fd)
        a[0] = a[1] = a[3] = 0                                # raw: no translation, no echo
        a[2] = termios.CS8 | termios.CREAD | termios.CLOCAL  # 8N1, no modem lines
        a[4] = a[5] = speed
        self.attrs = a
        self.poller = select.poll()
        self.poller.register(self.fd, select.POLLIN)
        self.vmin = None
        self.bus_ns = 0  # time spent on transactions, for the report

    def _expect(self, n):
        """Reads wait for n bytes, or 0.1 s of silence after one (VTIME)."""
        if self.vmin != n:
            self.attrs[6][termios.VMIN], self.attrs[6][termios.VTIME] = n, 1
            termios.tcsetattr(self.fd, termios.TCSANOW, self.attrs)
            self.vmin = n

    def transact(self, ins, params, n_params):
        """Sends an instruction, returns the status's params. The reply's
        first byte is waited for 100 ms at most (poll), the rest by VMIN:
        the bytes of a status with n_params, and any that stuffing added
        (its length field says how many)."""
        t0 = time.monotonic_ns()
        n = STATUS_OVERHEAD + n_params
        self._expect(n)
        os.write(self.fd, instruction(self.id, ins, params))
        if not self.poller.poll(100):
            raise BusError("servo %d does not answer" % self.id)
        raw = os.read(self.fd, n)
        if len(raw) >= 7 and raw[:4] == b"\xff\xff\xfd\x00":
            more = 7 + int.from_bytes(raw[5:7], "little") - len(raw)
            if 0 < more < 256:
                self._expect(more)
                raw += os.read(self.fd, more)
        self.bus_ns += time.monotonic_ns() - t0
        if len(raw) < n or raw[:4] != b"\xff\xff\xfd\x00" or raw[4] != self.id or raw[7] != 0x55:
            raise BusError("bad status packet %s" % raw.hex())
        if crc16(raw[:-2]) != int.from_bytes(raw[-2:], "little"):
            raise BusError("status CRC mismatch %s" % raw.hex())
        payload = unstuff(raw[7:-2])  # 0x55, error, params
        if payload[1] & 0x7F:
            raise BusError("status error 0x%02x" % payload[1])
        return payload[2:]

    def write(self, addr, value, size):
        self.transact(WRITE, addr.to_bytes(2, "little") + value.to_bytes(size, "little", signed=True), 0)

    def read_state(self):
        """(Present Position in counts, Present Velocity in 0.229 rpm)."""
        p = self.transact(READ, PRESENT_VELOCITY.to_bytes(2, "little") + (8).to_bytes(2, "little"), 8)
        return int.from_bytes(p[4:8], "little", signed=True), int.from_bytes(p[0:4], "little", signed=True)


# ---- timing ------------------------------------------------------------------

# clock_nanosleep on an absolute CLOCK_MONOTONIC deadline, as a C control
# loop paces itself (Python 3.11's time module has no wrapper for it).
_libc = ctypes.CDLL(None, use_errno=True)
CLOCK_MONOTONIC, TIMER_ABSTIME = 1, 1


class _Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


def sleep_until(deadline_ns):
    ts = _Timespec(deadline_ns // 1000000000, deadline_ns % 1000000000)
    while True:
        r = _libc.clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, ctypes.byref(ts), None)
        if r != errno.EINTR:
            return


def burn(ms):
    """ms of this program's CPU, by its CPU clock: the heavier law."""
    end = time.thread_time_ns() + int(ms * 1e6)
    x = 1
    while time.thread_time_ns() < end:
        for _ in range(200):
            x = (x * 1103515245 + 12345) & 0xFFFFFFFF
    return x


# ---- control -----------------------------------------------------------------

stop = False


def on_signal(signum, frame):
    global stop
    stop = True


def wrap_pi(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def goal_current(err, omega, kp, kd):
    torque = -kp * err - kd * omega
    units = round(torque / TORQUE_PER_AMP / CURRENT_UNIT)
    return max(-MAX_CURRENT, min(MAX_CURRENT, units))


def main():
    ap = argparse.ArgumentParser(description="Balance a pendulum through a Dynamixel servo.")
    ap.add_argument("--port", default="/dev/ttyUSB0")
    ap.add_argument("--baud", type=int, default=1000000)
    ap.add_argument("--id", type=int, default=1)
    ap.add_argument("--rate", type=float, default=100.0, metavar="HZ")
    ap.add_argument("--seconds", type=float, default=5.0, metavar="S")
    ap.add_argument("--work-ms", type=float, default=0.0, metavar="MS")
    # Tuned for the example's rod (1 kg, 1 m: 0.33 kg*m^2 about the hinge,
    # 4.9 N*m of gravity at 90 degrees, more than the servo's 4.1): a
    # closed loop of about 10 rad/s, damped (0.8 of critical).
    ap.add_argument("--kp", type=float, default=38.0, metavar="N*m/rad")
    ap.add_argument("--kd", type=float, default=5.3, metavar="N*m*s/rad")
    p = ap.parse_args()
    if p.rate <= 0 or p.seconds <= 0 or p.work_ms < 0:
        print("balance.py: --rate and --seconds must be positive, --work-ms not negative", file=sys.stderr)
        return 2
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    try:
        servo = Servo(p.port, p.baud, p.id)
        servo.write(TORQUE_ENABLE, 0, 1)                 # the mode is EEPROM: torque off first
        servo.write(OPERATING_MODE, CURRENT_MODE, 1)
        servo.write(GOAL_CURRENT, 0, 2)
        servo.write(TORQUE_ENABLE, 1, 1)
        servo.bus_ns = 0                                 # (the report counts the loop's)
    except (OSError, BusError) as e:
        print("balance.py: %s: %s" % (p.port, e), file=sys.stderr)
        return 1

    period = int(1e9 / p.rate)
    start = time.monotonic_ns()
    end = start + int(p.seconds * 1e9)
    deadline = start
    cycles = misses = 0
    worst = 0.0
    err = 0.0
    try:
        while not stop and time.monotonic_ns() < end:
            position, velocity = servo.read_state()
            err = wrap_pi((position - 2048) / COUNTS_PER_RAD - math.pi)
            if p.work_ms > 0:
                burn(p.work_ms)
            servo.write(GOAL_CURRENT, goal_current(err, velocity * VELOCITY_UNIT, p.kp, p.kd), 2)
            cycles += 1
            now = time.monotonic_ns()
            if now > end - 2000000000:
                worst = max(worst, abs(err))
            deadline += period
            if now > deadline:
                misses += 1
            sleep_until(deadline)
        elapsed = (time.monotonic_ns() - start) / 1e9
        bus_ms = servo.bus_ns / 1e6 / max(cycles, 1)
        servo.write(TORQUE_ENABLE, 0, 1)
    except BusError as e:
        if stop:  # (stopped mid-transaction: under tcs-run -d the bus ends with the run)
            print("balance.py: stopped after %d cycles" % cycles, file=sys.stderr)
            return 0
        print("balance.py: %s" % e, file=sys.stderr)
        return 1
    rate = cycles / elapsed if elapsed > 0 else 0.0
    balanced = worst < 0.1 and cycles > 0
    print("balance: %d cycles in %.3f s (%.1f Hz), %d deadline misses, bus %.3f ms a cycle, final angle from "
          "upright %.3f rad, worst over the last 2 s %.3f rad: %s"
          % (cycles, elapsed, rate, misses, bus_ms, err, worst, "BALANCED" if balanced else "FELL"))
    print("cycles=%d rate_hz=%.3f misses=%d bus_ms=%.4f worst_last2s=%.6f balanced=%d"
          % (cycles, rate, misses, bus_ms, worst, balanced))
    return 0


if __name__ == "__main__":
    sys.exit(main())
