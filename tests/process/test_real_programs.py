"""Programs nobody wrote for tcs, from Debian (issue 6), run under tcs-run
to completion in virtual time: coreutils timeout, sleep and date; signals
one process sends another (a shell's kill, Python's os.kill); rt-tests'
cyclictest and stress-ng's cyclic stressor, which ask for real-time
priorities (SCHED_FIFO 80, SCHED_DEADLINE) that tcs keeps below its own."""

import os
import re
import time

from harness import AHEAD, PROGRAMS, PYTHON, SLACK, check, main, need_tool, prog, tcs


def virtual_s(r):
    m = re.search(r"([0-9.]+) (s|ms) virtual", r.stderr)
    check(m is not None, "tcs-run's summary gives the virtual time", r)
    return float(m.group(1)) / (1000 if m.group(2) == "ms" else 1)


UNIT = {"s": 1e9, "ms": 1e6, "us": 1e3, "ns": 1}


def kernel_cpu_of(mode, *argv, timeout=60):
    """argv under tcs-run in mode, started by tests/programs/kernel_cpu_of:
    the result, how long it took on kernel_cpu_of's clock (s), and the CPU
    the kernel charged the whole tree meanwhile (s), read with system calls
    of its own: a bound from the kernel's account, not from tcs's summary."""
    r = tcs("-m", mode, "--", prog("kernel_cpu_of"), *argv, timeout=timeout)
    v = r.values()
    check("took_ns" in v and "tree_kernel_cpu_ns" in v, "%s: kernel_cpu_of reports" % argv[0], r)
    return r, int(v["took_ns"]) / 1e9, int(v["tree_kernel_cpu_ns"]) / 1e9


def wall_s(r):
    """tcs-run's own wall time of the run, from its summary."""
    m = re.search(r" virtual in ([0-9.]+) (s|ms|us|ns) wall", r.stderr)
    check(m is not None, "tcs-run's summary gives the wall time", r)
    return float(m.group(1)) * UNIT[m.group(2)] / 1e9


def test_timeout_ends_a_sleep_at_its_limit():
    for mode in ("lockstep", "cpu"):
        # (limit, command, its exit status, the virtual time it takes: the
        # limit, a timer's signal, is exact; a sleep that ends first ends
        # its timer slack late, docs/DESIGN.md §2)
        for args, status, took in ((["timeout", "2", "sleep", "10"], 124, 2.0),
                                   (["timeout", "3", "sleep", "1"], 0, 1.0 + SLACK / 1e9),
                                   (["timeout", "-s", "INT", "1.5", "sleep", "5"], 124, 1.5)):
            r, t, cpu = kernel_cpu_of(mode, *args, timeout=30)
            print("  %-8s %-28s exit %d after %.6f s" % (mode, " ".join(args), r.returncode, t))
            check(r.returncode == status, "%s: %s exits %d" % (mode, " ".join(args), status), r)
            # cpu mode adds at most what the programs computed: timeout's
            # CPU (its start before it arms its timer, its end after) and
            # its child's (which starts at timeout's time, on a CPU of its
            # own), no more than the kernel charged them (kernel_cpu_of's
            # own included), and what its last clock read runs ahead.
            most = took if mode == "lockstep" else took + cpu + AHEAD / 1e9
            check(took <= t <= most, "%s: %s takes %.6f s of virtual time and what it computed (to %.6f s), not %.6f"
                  % (mode, " ".join(args), took, most, t), r)


def test_a_signal_acts_at_the_senders_virtual_time():
    # A shell kills its background sleep after 1 s: the sleep dies then.
    r = tcs("-m", "lockstep", "--no-slack", "--", "sh", "-c", "sleep 10 & p=$!; sleep 1; kill $p; wait $p; echo status=$?",
            timeout=30)
    check(r.values().get("status") == "143", "the sleep died of SIGTERM (status 143)", r)
    check(virtual_s(r) == 1.0, "the run takes 1 s of virtual time, not the sleep's 10", r)
    # A handler in the receiver runs at the sender's time: Python's
    # time.sleep(10) in a child, interrupted after 0.5 s.
    script = """
import os, signal, sys, time
class Woken(Exception):
    pass
def woken(*_):
    raise Woken()
t0 = time.monotonic()
pid = os.fork()
if pid == 0:
    signal.signal(signal.SIGUSR1, woken)
    try:
        time.sleep(10)
    except Woken:
        print("handler_at=%.9f" % (time.monotonic() - t0), flush=True)
    os._exit(0)
time.sleep(0.5)
os.kill(pid, signal.SIGUSR1)
os.waitpid(pid, 0)
print("parent_done=%.9f" % (time.monotonic() - t0))
"""
    # The parent sends it after its sleep: 0.5 s, its 50 us of slack and
    # a few clock reads' 25 ns (spins' reads, with an epoch). Its news
    # reaches the coordinator before the signal does (the child's wait,
    # ended by it, once ended at the world's time, before the sender's).
    r = tcs("-q", "-m", "lockstep", "--epoch", "0", "--", PYTHON, "-c", script, timeout=30)
    v = r.values()
    print("  child's handler at %s s, parent done at %s s" % (v.get("handler_at"), v.get("parent_done")))
    sent = float(v.get("parent_done", "0"))
    check(0.50005 <= sent < 0.50005 + 1e-6, "the parent sends it at 0.50005 s", r)
    check(v.get("handler_at") == v.get("parent_done"), "the child's handler runs at the sender's time", r)


def test_date_tells_virtual_time():
    before = time.time_ns()
    r = tcs("-q", "-m", "lockstep", "--", "sh", "-c", "date +first=%s%N; sleep 5; date +second=%s%N", timeout=30)
    after = time.time_ns()
    v = r.values()
    first, second = int(v["first"]), int(v["second"])
    print("  date: %s, then %s" % (v["first"], v["second"]))
    # Virtual realtime starts at the real one, read when the run starts;
    # in lockstep nothing before the first date costs virtual time.
    check(before <= first <= after, "virtual wall-clock time starts at the real one: %d, within %d..%d" %
          (first, before, after), r)
    # sleep's 5 s end with its timer slack, and its shell learns of its end
    # then (it once reaped it at 5 s: its own look for it came first, in the
    # same step, where the exit had happened already).
    check(second - first == 5 * 10**9 + SLACK, "5 s and the timer slack apart, exactly", r)


def test_a_child_outside_tcs_is_said_and_waited_for_in_real_time():
    # A static program started by a shell (dash starts it with vfork: it
    # never registers), and one exec'd without LD_PRELOAD by a forked,
    # registered child: each runs 0.5 real seconds, which its parent's
    # wait for it takes as it would in real time.
    static = os.path.join(PROGRAMS, "static_hello")
    for how, command, name in (("static", static + " 0.5; sleep 1", "static_hello"),
                               ("no LD_PRELOAD", "env -u LD_PRELOAD sleep 0.5; sleep 1", "sleep")):
        r = tcs("-m", "lockstep", "--", "sh", "-c", command, timeout=30)
        t = virtual_s(r)
        print("  %-13s %.3f s virtual" % (how, t))
        check(r.returncode == 0, "%s: exit 0" % how, r)
        check(re.search(r"warning: process \d+ \(%s\).* runs in real time" % name, r.stderr) is not None,
              "%s: said once to run in real time" % how, r)
        check(r.stderr.count("runs in real time") == 1, "%s: said once" % how, r)
        # 1 s of sleep in virtual time, and the wait for the child in real
        # time: virtual time passes at real time's pace meanwhile (never
        # ahead of it: scheduler.cc arm_idle_step), the end looked for at
        # each step. So at least a step, and no more than the run's wall
        # time. The registered child that exec'd without the preload is
        # first waited for as any child, 100 ms of virtual time at once
        # (hooks_process.c: a wait looks again every 100 ms) before the
        # coordinator can know it runs in real time. (How much of the
        # child's 0.5 s the wait covers depends on when, in real time, the
        # parent begins it: the child sleeps first; no figure tells.)
        first_look = 0.1 if how == "no LD_PRELOAD" else 0
        check(1.001 <= t <= 1.0 + wall_s(r) + first_look + 0.0005,
              "%s: the wait for it passes in real time (%.3f s in all, %.3f s wall)" % (how, t, wall_s(r)), r)


AHEAD_US = AHEAD // 1000

CYCLIC = re.compile(r"C:\s*(\d+)\s+Min:\s*(\d+)\s+Act:\s*(\d+)\s+Avg:\s*(\d+)\s+Max:\s*(\d+)")


def test_cyclictest_runs_to_completion():
    need_tool("cyclictest", "rt-tests")
    # Lockstep: every wake-up exactly on time, whatever priority it asks.
    r = tcs("-m", "lockstep", "--", "cyclictest", "-l", "1000", "-i", "1000", "-p", "80", "-m", "-q", timeout=60)
    m = CYCLIC.search(r.stdout)
    check(r.returncode == 0 and m is not None, "cyclictest -p 80 ends and reports", r)
    loops, lat_min, _, avg, lat_max = map(int, m.groups())
    print("  lockstep: %d loops, latency min %d avg %d max %d us, %.3f s virtual" %
          (loops, lat_min, avg, lat_max, virtual_s(r)))
    check(loops == 1000 and lat_max == 0, "1000 loops, each woken at its time exactly", r)
    # Its thread's 1000 loops of 1 ms end at 1 s: real-time, its sleeps have
    # no timer slack. Its main thread, a normal one, looks at them every
    # 10.05 ms (usleep(10000) and its 50 us of slack), so at 1.005 s sees
    # them done, leaves its loop after the next sleep (1.015 s), then
    # sleeps 50 ms (and 50 us) before it stops the thread: 1.065 s.
    check(virtual_s(r) == 1.065, "1000 loops of 1 ms take 1 s of virtual time, cyclictest's end 65 ms more "
          "(its main thread's sleeps, each 50 us of slack late)", r)
    check("lowered to 2" in r.stderr, "its priority 80 is lowered below the coordinator's, and it says so", r)
    # cpu mode: a wake-up is late by what the program computed after its
    # due time (the hooks' return, the clock read; a pause of the machine
    # there is charged as CPU, as on hardware), and the read may run ahead
    # by 20 us (AHEAD_US). So no loop is later than all the CPU the run was
    # charged; and as those spans of the loops do not overlap (cyclictest
    # skips a release already past), their sum is at most that too, their
    # mean (cyclictest's, in whole microseconds) that over the loops.
    # (None a period late, as on an idle machine, is not a rule here: one
    # loop was 1.38 ms late in a run charged 24 ms in all, and cyclictest
    # prints no figure of a loop's own CPU to tell a pause.)
    # (The CPU: what the kernel charged it, by kernel_cpu_of, which started it.)
    r, _, cpu = kernel_cpu_of("cpu", "cyclictest", "-l", "1000", "-i", "1000", "-q")
    m = CYCLIC.search(r.stdout)
    check(r.returncode == 0 and m is not None, "cyclictest ends and reports in cpu mode", r)
    loops, lat_min, _, avg, lat_max = map(int, m.groups())
    cpu_us = cpu * 1e6
    print("  cpu mode: %d loops, latency min %d avg %d max %d us (its CPU %.1f us: mean at most %.1f)" %
          (loops, lat_min, avg, lat_max, cpu_us, cpu_us / 1000 + AHEAD_US))
    # (And each wake its thread's timer slack late: cyclictest without -p
    # runs a normal thread.)
    slack_us = SLACK / 1000
    check(loops == 1000 and lat_max <= cpu_us + AHEAD_US + slack_us, "1000 loops, none later than its CPU", r)
    check(slack_us <= avg <= cpu_us / 1000 + AHEAD_US + slack_us,
          "late by its timer slack and what it computes: %d us on average" % avg, r)


def test_stress_ng_cyclic_runs_to_completion():
    need_tool("stress-ng", "stress-ng")
    args = ["stress-ng", "--cyclic", "1", "--cyclic-ops", "1000", "--cyclic-method", "clock_ns", "--cyclic-sleep",
            "1000", "-t", "5", "--metrics-brief"]
    for mode in ("lockstep", "cpu"):
        r, _, cpu = kernel_cpu_of(mode, *args)
        out = r.stdout + r.stderr
        ops = re.search(r"cyclic\s+(\d+)\s+[0-9.]+\s", out)
        mean = re.search(r"cyclic:\s+mean:\s+([0-9.]+) ns", out)
        check(r.returncode == 0 and ops is not None and mean is not None, "%s: stress-ng ends and reports" % mode, r)
        print("  %-8s %s cycles, mean latency %s ns, %.3f s virtual" %
              (mode, ops.group(1), mean.group(1), virtual_s(r)))
        check(int(ops.group(1)) == 1000, "%s: 1000 cycles measured" % mode, r)
        # None in lockstep; in cpu mode what the stressor computed after
        # each due time, as for cyclictest above: on average at most its
        # CPU over the cycles (all the kernel charged the run's processes,
        # its own among them), + AHEAD.
        most = 0.0 if mode == "lockstep" else cpu * 1e9 / 1000 + AHEAD_US * 1000
        check(float(mean.group(1)) <= most,
              "%s: latencies of a virtual clock: %s ns on average, at most %.0f" % (mode, mean.group(1), most), r)
        check("SCHED_DEADLINE granted as SCHED_FIFO" in r.stderr, "%s: its SCHED_DEADLINE is kept below tcs" % mode, r)


if __name__ == "__main__":
    main(globals())
