"""The start the CAN socket tests' programs share (test_can_socket.py puts it
before each program's text): raw CAN_RAW sockets bound to can0, frames as
struct can_frame, and a sleep to an absolute time on a clock, so that what
a program does next happens at a time the test knows exactly (lockstep,
--no-slack: a wait ends at its deadline and sends cost no virtual time)."""

PRELUDE = """\
import ctypes, errno, os, select, socket, struct, sys, time
SOL_CAN_RAW, CAN_RAW_FILTER, CAN_RAW_ERR_FILTER = 101, 1, 2
CAN_RAW_LOOPBACK, CAN_RAW_RECV_OWN_MSGS = 3, 4
SO_TIMESTAMPNS, SO_TIMESTAMPING, SO_RXQ_OVFL, SO_DOMAIN = 35, 37, 40, 39
SOF_RX_SOFTWARE, SOF_SOFTWARE = 8, 16
CLOCK_REALTIME, CLOCK_MONOTONIC, TIMER_ABSTIME = 0, 1, 1
libc = ctypes.CDLL(None, use_errno=True)

class timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]

def sleep_until(clock, t_ns):
    ts = timespec(t_ns // 10**9, t_ns % 10**9)
    while libc.clock_nanosleep(clock, TIMER_ABSTIME, ctypes.byref(ts), None) == errno.EINTR:
        pass

def sock(bind=True):
    s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    if bind:
        s.bind(("can0",))
    return s

def frame(can_id, data):
    return struct.pack("=IB3x8s", can_id, len(data), data)

def unframe(raw):
    can_id, length = struct.unpack("=IB", raw[:5])
    return can_id, raw[8:8 + length]

def stamps(cmsgs, kind):
    return [d for level, t, d in cmsgs if level == socket.SOL_SOCKET and t == kind]

def out(*words):
    print(*words, flush=True)
"""
