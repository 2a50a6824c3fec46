"""Dynamixel Protocol 2.0 on a tty, with os and termios only, for the serial
process tests' programs (dxl_probe.py): the e-Manual's CRC-16, instruction
packets, a line in raw mode at a baud, and the clocks the tests read.
Written from the e-Manual's packet description, not from the SDK: a test
of the emulation should not share its author's reading of the protocol
with a library's."""

import os
import termios
import time

from kernel_clock import kernel_cpu_ns

PING, READ, WRITE = 0x01, 0x02, 0x03
BROADCAST = 0xFE
# Control table addresses (XM430-W350).
RETURN_DELAY_TIME, OPERATING_MODE, TORQUE_ENABLE = 9, 11, 64
GOAL_POSITION, PRESENT_POSITION = 116, 132

# termios speed codes by rate.
SPEEDS = {r: getattr(termios, "B%d" % r) for r in (9600, 19200, 57600, 115200, 1000000, 2000000)}


def crc16(data):
    """CRC-16 (polynomial 0x8005, no reflection, initial 0), as the
    e-Manual's update_crc computes it."""
    crc = 0
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def packet(dxl_id, instruction, params=b""):
    """An instruction packet: header, ID, length (instruction, params and
    CRC), instruction, params, CRC. (The tests' params never hold FF FF FD:
    no byte stuffing.)"""
    body = bytes([0xFF, 0xFF, 0xFD, 0x00, dxl_id]) + (len(params) + 3).to_bytes(2, "little")
    body += bytes([instruction]) + params
    return body + crc16(body).to_bytes(2, "little")


def read_packet(dxl_id, addr, n):
    return packet(dxl_id, READ, addr.to_bytes(2, "little") + n.to_bytes(2, "little"))


def write_packet(dxl_id, addr, data):
    return packet(dxl_id, WRITE, addr.to_bytes(2, "little") + data)


def status_len(n_params):
    """A status packet's bytes: header 4, ID, length 2, 0x55, error, the
    params, CRC 2."""
    return 11 + n_params


def parse_status(raw):
    """(id, error, params) of a whole status packet, its byte stuffing
    undone, or None if it is not one or its CRC is wrong."""
    if len(raw) < 11 or raw[:4] != b"\xff\xff\xfd\x00" or raw[7] != 0x55:
        return None
    length = int.from_bytes(raw[5:7], "little")
    if len(raw) != 7 + length or crc16(raw[:-2]) != int.from_bytes(raw[-2:], "little"):
        return None
    payload = raw[7:-2].replace(b"\xff\xff\xfd\xfd", b"\xff\xff\xfd")
    return raw[4], payload[1], payload[2:]


def open_line(path, baud, vmin=0, vtime=0):
    """The tty in raw mode (8N1, no flow control) at baud."""
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
    set_line(fd, baud, vmin, vtime)
    return fd


def set_line(fd, baud, vmin, vtime):
    a = termios.tcgetattr(fd)
    a[0] = 0                                                # iflag: no translation, no XON/XOFF
    a[1] = 0                                                # oflag: no post-processing
    a[2] = termios.CS8 | termios.CREAD | termios.CLOCAL     # cflag: 8N1
    a[3] = 0                                                # lflag: raw, no echo
    a[4] = a[5] = SPEEDS[baud]
    a[6][termios.VMIN], a[6][termios.VTIME] = vmin, vtime
    termios.tcsetattr(fd, termios.TCSANOW, a)


def read_upto(fd, n):
    """Reads until n bytes or a read returns nothing (VMIN 0 and VTIME's
    timeout, with the line set so)."""
    got = b""
    while len(got) < n:
        r = os.read(fd, n - len(got))
        if not r:
            break
        got += r
    return got


def now():
    """(virtual monotonic ns, process CPU ns by the kernel's clock): a span's
    time and the CPU the program spent in it, which in cpu mode is what may
    make it late (the kernel's account: tcs charges no more)."""
    return time.monotonic_ns(), kernel_cpu_ns()


def settle():
    """A short sleep: the clock read after it is the wait's end, with no
    spin cost in lockstep, so the span measured next starts exactly there."""
    time.sleep(0.001)
