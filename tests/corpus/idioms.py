#!/usr/bin/env python3
"""idioms.py handler CALL INTERRUPTED | fork CALL: the idiom corpus's Python
cases (cases.py names them py-handler and py-fork), reporting as
the idioms program (tests/programs/idioms/) does, in key=value lines.

handler: a periodic signal.setitimer(ITIMER_REAL) of 2 ms whose SIGALRM
handler makes CALL, while the main flow loops over INTERRUPTED (sleep,
monotonic or pause), until 20 CALLs are done. Python runs a handler
between bytecodes, after the C call it interrupted returned EINTR; a
sleep is then resumed for what is left (PEP 475), which is checked here.
fork: two threads keep calling signal.setitimer, signal.getitimer and
time.monotonic; 20 children are forked, each makes CALL once, reports
through a pipe and leaves with os._exit.

CALLs: sleep (time.sleep 500 us: never early), monotonic (never back),
dev_read (os.open, os.read, os.close of the pendulum's state device: an
'angle velocity' line), dev_write (a torque line), setitimer (the
handler re-arms its timer; in a fork child, arms and disarms its own).
Natively the device is absent: counted as device_absent, no failure.
Exit 0 if every check held, 1 if not."""

import errno
import os
import re
import signal
import sys
import threading
import time

ROUNDS = 20
PERIOD = 0.002
SLEEP_NS = 500000
STATE = "/dev/tcs/pendulum/state"
TORQUE = "/dev/tcs/pendulum/torque"
RECORD = re.compile(rb"^[-+0-9.eE]+ +[-+0-9.eE]+\n")

stats = {"failures": 0, "absent": 0}
# sleeps: [count, min, max] of the CALL's (in the handler or the child) and
# of the interrupted flow's
sleeps = {"call": [0, None, None], "flow": [0, None, None]}
role = ["flow"]
first = []
seen = [0]


def fail(call, what, err=0):
    stats["failures"] += 1
    if not first:
        first.append("py.%s:%s:%s" % (call, what, errno.errorcode.get(err, err) if err else 0))


def do_sleep():
    t0 = time.monotonic_ns()
    time.sleep(SLEEP_NS / 1e9)
    took = time.monotonic_ns() - t0
    record(role[0], 1, took, took)
    if took < SLEEP_NS:
        fail("sleep", "ended_early")


def record(who, n, lo, hi):
    s = sleeps[who]
    s[0] += n
    if n:
        s[1] = lo if s[1] is None else min(s[1], lo)
        s[2] = hi if s[2] is None else max(s[2], hi)


def do_monotonic():
    # no less than what was seen before it began (a handler may read the
    # clock between this read and the comparison)
    before = seen[0]
    v = time.monotonic_ns()
    if v < before:
        fail("monotonic", "went_back")
    seen[0] = max(seen[0], v)


def device(path, flags):
    """The device's fd, or None where it is absent (natively)."""
    try:
        return os.open(path, flags)
    except FileNotFoundError:
        stats["absent"] += 1
    except OSError as e:
        fail("open", "open", e.errno)
    return None


def do_dev_read():
    fd = device(STATE, os.O_RDONLY)
    if fd is not None:
        data = os.read(fd, 256)
        if not RECORD.match(data):
            fail("dev_read", "record")
        os.close(fd)


def do_dev_write():
    fd = device(TORQUE, os.O_WRONLY)
    if fd is not None:
        if os.write(fd, b"0.1\n") != 4:
            fail("dev_write", "short_write")
        os.close(fd)


def do_setitimer(rearm):
    if rearm:
        old = signal.setitimer(signal.ITIMER_REAL, PERIOD, PERIOD)
        if abs(old[1] - PERIOD) > 1e-6 or not 0 < old[0] <= PERIOD:
            fail("setitimer", "old")
    else:
        old = signal.setitimer(signal.ITIMER_REAL, 10)
        left = signal.setitimer(signal.ITIMER_REAL, 0)[0]
        if old != (0.0, 0.0) or not 9 < left <= 10:
            fail("setitimer", "left")


def do_pause():
    signal.pause()


def call_of(name, in_handler):
    table = {"sleep": do_sleep, "monotonic": do_monotonic, "dev_read": do_dev_read,
             "dev_write": do_dev_write, "setitimer": lambda: do_setitimer(in_handler), "pause": do_pause}
    if name not in table:
        sys.exit("idioms.py: no call %s" % name)
    return table[name]


def report(calls, extra):
    ok = stats["failures"] == 0 and calls == ROUNDS
    lines = ["calls=%d" % calls, "failures=%d" % stats["failures"],
             "first_failure=%s" % (first[0] if first else "-"),
             "device_absent=%d" % stats["absent"]]
    for who in ("call", "flow"):
        n, lo, hi = sleeps[who]
        lines += ["%s_sleeps=%d" % (who, n), "%s_sleep_min_ns=%d" % (who, -1 if lo is None else lo),
                  "%s_sleep_max_ns=%d" % (who, -1 if hi is None else hi),
                  "%s_sleep_over_max_ns=%d" % (who, -1 if hi is None else hi - SLEEP_NS)]
    lines += extra + ["ok=%d" % ok]
    print("\n".join(lines), flush=True)
    return 0 if ok else 1


def run_handler(call, flow):
    make, loop = call_of(call, True), call_of(flow, False)
    claimed, done = [0], [0]

    def on_alarm(sig, frame):
        # Python runs a handler again inside one that sleeps: a call is
        # claimed before it is made, so that no more than ROUNDS are
        if claimed[0] < ROUNDS:
            claimed[0] += 1
            outer, role[0] = role[0], "call"
            make()
            role[0] = outer
            done[0] += 1

    signal.signal(signal.SIGALRM, on_alarm)
    signal.setitimer(signal.ITIMER_REAL, PERIOD, PERIOD)
    start = time.monotonic()
    while done[0] < ROUNDS and time.monotonic() - start < 5:  # gives up after 5 s
        loop()
    signal.setitimer(signal.ITIMER_REAL, 0)
    return report(done[0], ["handler_runs=%d" % done[0]])


def run_fork(call):
    make = call_of(call, False)
    stop = threading.Event()

    def churn():
        # a 10 s one-shot that never fires, re-armed again and again
        while not stop.is_set():
            for _ in range(16):
                signal.setitimer(signal.ITIMER_REAL, 10)
                signal.getitimer(signal.ITIMER_REAL)
                time.monotonic()
            time.sleep(0.0002)

    threads = [threading.Thread(target=churn) for _ in range(2)]
    for t in threads:
        t.start()
    calls = 0
    for _ in range(ROUNDS):
        r, w = os.pipe()
        pid = os.fork()
        if pid == 0:
            os.close(r)
            role[0] = "call"
            sleeps["call"] = [0, None, None]  # what the parent gathered is not the child's
            try:
                make()
            except Exception as e:  # a child must reach os._exit whatever happens
                fail(call, "raised %s" % type(e).__name__)
            n, lo, hi = sleeps["call"]
            os.write(w, ("%d %d %d %d %d %s\n" % (stats["failures"], stats["absent"], n, lo or 0, hi or 0,
                                                  first[0] if first else "-")).encode())
            os._exit(0 if stats["failures"] == 0 else 1)
        os.close(w)
        with os.fdopen(r) as f:
            got = f.read().split()
        _, status = os.waitpid(pid, 0)
        if len(got) != 6:
            fail(call, "child_no_report")
        else:
            stats["failures"] += int(got[0])
            stats["absent"] += int(got[1])
            record("call", int(got[2]), int(got[3]), int(got[4]))
            if got[5] != "-" and not first:
                first.append(got[5])
        if not (os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0):
            fail(call, "child_status")
        calls += 1
    stop.set()
    for t in threads:
        t.join()
    signal.setitimer(signal.ITIMER_REAL, 0)
    return report(calls, [])


def main(argv):
    if len(argv) == 4 and argv[1] == "handler":
        return run_handler(argv[2], argv[3])
    if len(argv) == 3 and argv[1] == "fork":
        return run_fork(argv[2])
    print(__doc__.splitlines()[0], file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
