#!/usr/bin/env python3
"""pendulum_pd: swing a pendulum up and balance it, at 1 kHz, as a plain
Python program that knows nothing of tcs. It reads "position velocity" lines
from the state device, writes a torque line to the torque device, and paces
itself with absolute deadlines on the monotonic clock -- on hardware the two
paths would be the drivers of a real encoder and motor. The same controller
as pendulum_pd.c, written the way a Python robotics program would be.

Control: energy pumping (the rod's energy driven towards that of the upright
rest, torque in the direction of motion, within the motor's limit) until the
pendulum comes near the top, then a PD law about the upright. Angle 0 hangs
down, pi is up; positive torque raises the angle.

  pendulum_pd.py [--rate HZ] [--seconds S] [--work-us N]
                 [--state PATH] [--torque PATH] [--length L] [--mass M]
                 [--limit N*m]

--work-us N burns N microseconds of this machine's CPU every cycle, standing
for a heavier control law; a target CPU --cpu-scale times slower takes that
many times longer for the same work. At the end it prints how it did: the
largest distance from upright over its last 2 seconds.

Pacing uses time.sleep() on the distance to the next absolute deadline:
Python 3.11 has no wrapper for clock_nanosleep(TIMER_ABSTIME) (time.sleep
itself sleeps until an absolute CLOCK_MONOTONIC deadline it computes).
"""

import argparse
import ctypes
import ctypes.util
import math
import platform
import signal
import sys
import time

stop = False


def on_signal(signum, frame):
    global stop
    stop = True


# ---- the stand-in for a heavier control law ---------------------------------

MASK64 = (1 << 64) - 1
sink = 0


def rounds(n):
    """n rounds of a 64-bit xorshift, the same integer loop as the C version."""
    global sink
    x = (sink + 88172645463325252) & MASK64
    for _ in range(n):
        x ^= (x << 13) & MASK64
        x ^= x >> 7
        x ^= (x << 17) & MASK64
    sink = x


# This machine's real CPU time. The raw system call is deliberate: it is the
# one clock a simulator leaves alone, so --work-us means microseconds of
# *this* CPU, and a slower target CPU (tcs-run --cpu-scale) takes longer for
# the same work, as it would on the robot. time.thread_time_ns() goes through
# the C library's clock_gettime(), which a simulator may answer with virtual
# time, so it is not used here; ctypes calls libc's syscall() instead.
class _Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


_SYS_CLOCK_GETTIME = {"x86_64": 228, "aarch64": 113, "arm64": 113}
_CLOCK_THREAD_CPUTIME_ID = 3
_libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
_libc.syscall.restype = ctypes.c_long


def real_cpu_s():
    nr = _SYS_CLOCK_GETTIME.get(platform.machine())
    if nr is None:
        raise OSError("pendulum_pd.py: no clock_gettime system call number for " + platform.machine())
    ts = _Timespec()
    if _libc.syscall(ctypes.c_long(nr), ctypes.c_long(_CLOCK_THREAD_CPUTIME_ID), ctypes.byref(ts)) != 0:
        err = ctypes.get_errno()
        raise OSError(err, "clock_gettime system call failed")
    return ts.tv_sec + ts.tv_nsec / 1e9


def rounds_per_us():
    # Rounds per microsecond of this CPU: the fastest of five rounds of about
    # 5 ms. On a shared machine a round can run slow (a busy neighbour core),
    # and one slow round alone would make every cycle's work short by as
    # much. Short, about 30 ms in all, since the world runs meanwhile.
    n = 1000
    while True:
        t0 = real_cpu_s()
        rounds(n)
        dt = real_cpu_s() - t0
        if dt >= 0.001:
            break
        n *= 2
    n = int(n * 0.005 / dt) + 1
    best = 0.0
    for _ in range(5):
        t0 = real_cpu_s()
        rounds(n)
        dt = real_cpu_s() - t0
        if dt > 0:
            best = max(best, n / (dt * 1e6))
    return best


# ---- control -----------------------------------------------------------------


def wrap_pi(a):
    a = math.fmod(a + math.pi, 2 * math.pi)
    return a + math.pi if a < 0 else a - math.pi


def clamp(v, lim):
    return lim if v > lim else -lim if v < -lim else v


def control(p, theta, omega):
    g = 9.81
    inertia = p.mass * p.length * p.length / 3
    err = wrap_pi(theta - math.pi)  # 0 when upright
    if abs(err) < 0.3 and abs(omega) < 3.0:
        return clamp(-40.0 * err - 8.0 * omega, p.limit)
    energy = 0.5 * inertia * omega * omega + p.mass * g * p.length / 2 * (1 - math.cos(theta))
    target = p.mass * g * p.length
    push = 1 if omega >= 0 else -1
    return clamp(8.0 * (target - energy) * push, p.limit)


def main():
    prog = sys.argv[0]
    ap = argparse.ArgumentParser(description="Swing a pendulum up and balance it.")
    ap.add_argument("-r", "--rate", type=float, default=1000.0, metavar="HZ")
    ap.add_argument("-s", "--seconds", type=float, default=0.0, metavar="S")
    ap.add_argument("-w", "--work-us", type=float, default=0.0, metavar="N")
    ap.add_argument("--state", default="/dev/tcs/pendulum/state", metavar="PATH")
    ap.add_argument("--torque", default="/dev/tcs/pendulum/torque", metavar="PATH")
    ap.add_argument("--length", type=float, default=1.0, metavar="L")
    ap.add_argument("--mass", type=float, default=1.0, metavar="M")
    ap.add_argument("--limit", type=float, default=5.0, metavar="N*m")
    p = ap.parse_args()
    if p.rate <= 0 or p.work_us < 0:
        print(f"{prog}: --rate must be positive and --work-us not negative", file=sys.stderr)
        return 2
    try:
        state = open(p.state, "r")
    except OSError as e:
        print(f"{prog}: cannot open {p.state}: {e.strerror}", file=sys.stderr)
        return 1
    try:
        torque = open(p.torque, "w")
    except OSError as e:
        print(f"{prog}: cannot open {p.torque}: {e.strerror}", file=sys.stderr)
        return 1
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    work = int(p.work_us * rounds_per_us()) if p.work_us > 0 else 0

    # Absolute deadlines in integer nanoseconds of time.monotonic_ns(), so
    # they do not drift from rounding as a float sum of periods would.
    period = int(1e9 / p.rate)
    next_ns = time.monotonic_ns()
    start = time.monotonic()
    seconds = p.seconds
    worst_recent = 0.0
    theta = omega = 0.0
    cycles = misses = 0
    while not stop and (seconds <= 0 or time.monotonic() - start < seconds):
        line = state.readline()
        try:
            theta, omega = (float(f) for f in line.split()[:2])
        except ValueError:
            print(f"{prog}: bad state record", file=sys.stderr)
            return 1
        rounds(work)
        torque.write("%.6f\n" % control(p, theta, omega))
        torque.flush()
        cycles += 1
        # How upright it is over the last 2 s of the run.
        err = abs(wrap_pi(theta - math.pi))
        if seconds > 0 and time.monotonic() - start > seconds - 2 and err > worst_recent:
            worst_recent = err

        next_ns += period
        now_ns = time.monotonic_ns()
        if now_ns > next_ns:
            misses += 1
        time.sleep(max(0, next_ns - now_ns) / 1e9)
    elapsed = time.monotonic() - start
    rate = cycles / elapsed if elapsed > 0 else (math.inf if cycles else math.nan)
    balanced = 1 if seconds > 0 and worst_recent < 0.1 else 0
    print("pendulum_pd: %d cycles in %.3f s (%.1f Hz), %d deadline misses, final angle %.3f rad, "
          "worst distance from upright over the last 2 s %.3f rad: %s"
          % (cycles, elapsed, rate, misses, theta, worst_recent, "BALANCED" if balanced else "FELL"))
    print("cycles=%d rate_hz=%.3f misses=%d worst_last2s=%.6f balanced=%d"
          % (cycles, rate, misses, worst_recent, balanced))
    return 0


if __name__ == "__main__":
    sys.exit(main())
