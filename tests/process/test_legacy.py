"""Legacy idioms (docs/DESIGN.md, "Re-entrancy"; issue 35): a control law in
a SIGALRM handler, handlers that re-arm their own timers while main reads
them, handlers that sleep and set timers while main is inside other hooks,
and fork from a threaded program. Each hung tcs-run before; each must now
run as natively, in both modes, with nothing said about it."""

import math
import os
import tempfile

from harness import check, main, prog, tcs, trace_rows

MODES = ("cpu", "lockstep")
MS = 1000000


_machine = {}


def quiet(r, mode):
    """Nothing of this is a warning: tcs-run -q says no more than it says of
    a program that does nothing on this machine (where the TSC may not be
    used, or SCHED_FIFO is refused, it says so for every program)."""
    if mode not in _machine:
        _machine[mode] = tcs("-q", "-m", mode, "--", "true").stderr
    check(r.stderr == _machine[mode], "no warning from tcs beyond the machine's own:\n" + _machine[mode], r)


def test_control_law_in_a_sigalrm_handler_balances():
    for mode in MODES:
        with tempfile.TemporaryDirectory() as d:
            trace = os.path.join(d, "run.mcap")
            r = tcs("-q", "-m", mode, "-t", trace, "--", prog("legacy_alarm_pd"), "10", timeout=240)
            check(r.returncode == 0, "the handler controller ends by itself (%s)" % mode, r)
            quiet(r, mode)
            v = r.values()
            runs, gap = int(v["runs"]), int(v["max_gap_ns"])
            print("  %s: %d handler runs, largest gap %d ns" % (mode, runs, gap))
            check(v["bad_reads"] == "0", "every read of the state and write of the torque in the handler worked", r)
            # It stops once its clock, read first thing in the handler, is
            # 10 s past the first run's: the 10001st run at 10 s exactly in
            # lockstep; in cpu mode each run's read lies past its expiry by
            # what its delivery cost, so the 10001st, or the 10002nd when
            # that one's cost was less than the first's.
            if mode == "lockstep":
                check(runs == 10001 and gap == MS, "1000 handler runs a virtual second, each 1 ms after the last", r)
            else:
                check(runs in (10001, 10002), "1000 handler runs a virtual second: %d in 10 s" % runs, r)
            # The world, as the trace has it, not the controller's word:
            # upright (angle pi) within 0.1 rad over the last 2 s.
            steps = trace_rows(trace, "/tcs/step")
            end = int(steps[-1]["v_ns"])
            last = [float(s["joint.pendulum.hinge.position"]) for s in steps if int(s["v_ns"]) >= end - 2000 * MS]
            worst = max(abs(math.remainder(p - math.pi, 2 * math.pi)) for p in last)
            check(len(last) >= 1900 and worst < 0.1,
                  "the pendulum balances (%s): %.4f rad from upright at worst over the last 2 s" % (mode, worst), r)


def test_handlers_rearm_their_timers_while_main_reads_them():
    for mode in MODES:
        for kind in ("itimer", "posix"):
            r = tcs("-q", "-m", mode, "--", prog("legacy_rearm"), kind, "500", "1000", timeout=120)
            check(r.returncode == 0, "a handler re-arming its timer while main reads it (%s, %s)" % (kind, mode), r)
            quiet(r, mode)
            v = r.values()
            lo, hi = int(v["min_gap_ns"]), int(v["max_gap_ns"])
            print("  %s, %s: %s runs, gaps %d to %d ns, %s reads" % (mode, kind, v["runs"], lo, hi, v["reads"]))
            check(v["runs"] == "500" and v["seen_above"] == "0", "500 runs, never more left than was set", r)
            # Each run re-arms after its clock read, so the next comes a
            # period after that read or later: never sooner (in lockstep
            # exactly then, the re-arm costing nothing).
            if mode == "lockstep":
                check(lo == hi == MS, "in lockstep each run 1 ms after the last: %d to %d ns" % (lo, hi), r)
            else:
                check(lo > MS, "no run sooner than a period after the last: %d ns" % lo, r)


def test_handlers_sleep_and_set_timers_inside_other_hooks():
    outputs = []
    for mode in MODES + ("lockstep",):
        r = tcs("-q", "-m", mode, "--epoch", "0", "--", prog("legacy_handler_calls"), "200", timeout=120)
        check(r.returncode == 0, "handlers calling timer_settime, nanosleep, clock_gettime and setitimer (%s)" % mode,
              r)
        quiet(r, mode)
        v = r.values()
        print("  %s: %s SIGALRM and %s SIGUSR1 handler runs, %s sleeps, %s of them interrupted" %
              (mode, v["alarm_runs"], v["usr1_runs"], v["sleeps"], v["interrupted"]))
        check(v["early"] == "0" and int(v["alarm_runs"]) >= 200 and int(v["usr1_runs"]) >= 200,
              "no sleep ended early, every handler ran", r)
        if mode == "lockstep":
            outputs.append(r.stdout)
    check(outputs[0] == outputs[1], "lockstep is deterministic, handlers and all:\n%s\n%s" % tuple(outputs))


def test_fork_from_a_threaded_program():
    for mode in MODES:
        r = tcs("-q", "-m", mode, "--", prog("legacy_fork_threads"), "20", timeout=120)
        check(r.returncode == 0, "fork while two threads are inside timer hooks (%s)" % mode, r)
        quiet(r, mode)
        check(r.values() == {"reaped": "20", "failed": "0"}, "20 children and 7 grandchildren ended well", r)


if __name__ == "__main__":
    main(globals())
