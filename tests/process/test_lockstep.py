"""Lockstep mode and the hooked calls whose results are exact in virtual
time: sleeps, clocks, multiplexer timeouts, EINTR, determinism."""

import os
import re
import shutil
import tempfile
import textwrap
import time

from harness import AHEAD, READ, PYTHON, SLACK, TCS_RUN, check, main, need_tool, prog, run, tcs


def ns(value, unit):
    return float(value) * {"s": 1e9, "ms": 1e6, "us": 1e3, "ns": 1}[unit]


def takes_no_wall_time(command, seconds):
    """command, which sleeps `seconds`, in lockstep: the sleep waits for
    nothing real. Its wall time is what tcs-run costs with no virtual time
    at all (the same command sleeping 0 s, measured here just before) and
    the world's steps through the sleep, at their median wall cost (the
    summary's); four times that allows for the coordinator's own part of a
    step (about the world's here) and a shared machine's pauses. (That
    bound tells lockstep from real time only while it is well under the
    sleep: a few hundredths of it here, and checked to be under a tenth.)"""
    base = tcs("-m", "lockstep", "--", *[c.replace(str(seconds), "0") for c in command], timeout=20)
    check(base.returncode == 0 and "0 ns virtual" in base.stderr, "%s: 0 s of virtual time" % command, base)
    r = tcs("-m", "lockstep", "--", *command, timeout=20)
    check(r.returncode == 0, "%s exits 0" % command, r)
    check("%d.000 s virtual" % seconds in r.stderr, "the summary reports %d s of virtual time" % seconds, r)
    m = re.search(r"world: (\d+) steps; wall cost per step min [\d.]+ \w+, median ([\d.]+) (\w+)", r.stderr)
    check(m is not None and int(m.group(1)) == seconds * 1000, "a step a virtual ms", r)
    step = ns(m.group(2), m.group(3)) / 1e9
    most = 4 * (base.wall + int(m.group(1)) * step)
    print("  %s: %.3f s of wall time (%.3f s without the sleep, steps %.2f us): at most %.3f" %
          (" ".join(command), r.wall, base.wall, step * 1e6, most))
    check(most < seconds / 10 and r.wall <= most, "%s in lockstep took %.3f s of wall time" % (command, r.wall), r)


def test_sleep_30_takes_no_wall_time():
    takes_no_wall_time(["sleep", "30"], 30)


def test_a_program_that_execs_stays_in_virtual_time():
    # The shell replaces itself with sleep: the new image says HELLO again.
    # (30 s, as above: with 7 the bound came to a tenth of the sleep when
    # tcs-run itself took 170 ms on a loaded machine, and told nothing.)
    takes_no_wall_time(["sh", "-c", "exec sleep 30"], 30)


def test_python_sleep_loop_sees_exactly_5s():
    script = textwrap.dedent("""
        import time
        t0 = time.monotonic()
        for _ in range(500):
            time.sleep(0.01)
        print("elapsed=%.9f" % (time.monotonic() - t0))
    """)
    r = tcs("-q", "-m", "lockstep", "--epoch", "0", "--", PYTHON, "-c", script, timeout=30)
    check(r.returncode == 0, "python exits 0", r)
    # Each sleep ends its 50 us of timer slack late, and the next counts
    # from there. The first sleep's own clock read follows t0's with no
    # wait between: a spin's read, 25 ns with an epoch (the others each
    # follow a sleep, and cost nothing).
    check(r.values()["elapsed"] == "5.025000025", "500 x time.sleep(0.01) is exactly 500 x 10.05 ms and a read", r)


def cpu_clock_readings(loops):
    """periodic's loop of `loops` round trips (no work) in lockstep under
    strace: (the controller's CPU-clock readings, the coordinator's of the
    controller's clock, clock_gettime system calls in all, the run)."""
    strace = need_tool("strace", "strace")
    out = os.path.join(tempfile.mkdtemp(prefix="tcs-test-lockstep-"), "strace.txt")
    r = run([strace, "-f", "-qq", "-e", "trace=clock_gettime", "-o", out, TCS_RUN, "-q", "-m", "lockstep",
             prog("periodic"), "1000", str(loops / 1000), "0"], timeout=120)
    check(r.returncode == 0 and r.values()["loops"] == str(loops), "%d cycles, each a round trip" % loops, r)
    calls = [l for l in open(out) if "clock_gettime(" in l]
    own = [l for l in calls if "clock_gettime(CLOCK_PROCESS_CPUTIME_ID" in l or "clock_gettime(CLOCK_THREAD" in l]
    other = [l for l in calls if re.search(r"clock_gettime\((0x[0-9a-f]+|-\d+)", l)]
    shutil.rmtree(os.path.dirname(out))
    return len(own), len(other), len(calls), r


def test_a_round_trip_reads_no_cpu_clock():
    # Computation is free in lockstep, so a wait's round trip needs no
    # reading of the controller's CPU clock, a system call that costs 50x a
    # native clock read on some machines. The preload reads it for real at
    # a wait's return only for the first 8 (learning what its hooks cost)
    # and every 64th after (cpu_estimate.c, tcs_exit_mark); a request's
    # claim reads it only when its estimate went stale (the loop stopped
    # for over 20 us between a wait's return and its next request, or the
    # coordinator ran meanwhile): those are events of the machine and of
    # the coordinator's timers, not of round trips, allowed here as many
    # again as the design's own readings. strace (which slows everything)
    # counts the readings on both sides: a process CPU clock in the
    # controller, a clock id of another process's in the coordinator.
    # What does not grow with the round trips (start-up, the 8, the
    # program's own reads) is a run of 64 loops' (one full turn of 64).
    base, base_other, _, _ = cpu_clock_readings(64)
    own, other, calls, r = cpu_clock_readings(3000)
    marks = -(-(3000 - 64) // 64)
    print("  %d CPU-clock readings in 3000 round trips, %d in 64 (%d clock_gettime system calls in all); "
          "the coordinator's %d, %d; %.2f s wall" % (own, base, calls, other, base_other, r.wall))
    check(own - base <= 2 * marks, "a reading every 64th round trip (%d more for 2936 more, at most %d)" %
          (own - base, 2 * marks))
    # The coordinator reads it at its own timers' ticks (the progress
    # every 250 ms of wall time; no watchdog for one controller), none a
    # round trip.
    check(other - base_other <= r.wall / 0.25 + 1, "the coordinator's readings: %d more" % (other - base_other))


def test_same_epoch_same_timestamps():
    script = ("import time\nfor i in range(3):\n    time.sleep(0.25)\n"
              "    print('t=%d m=%d' % (time.time_ns(), time.monotonic_ns()))\n")
    runs = [tcs("-q", "-m", "lockstep", "--epoch", "2024-05-01T12:00:00Z", "--", PYTHON, "-c", script)
            for _ in range(2)]
    # (Each 0.25 s sleep ends 50 us late: its timer slack.) Python's
    # start-up reads the clock, 25 ns each after the first with an epoch
    # (spins in lockstep), so the first sleep begins a whole number of
    # those in. Each line's time.time() follows a sleep (free), its
    # time.monotonic() costs a read, and the next sleep reads the monotonic
    # clock for its deadline (CPython's clock_nanosleep TIMER_ABSTIME): each
    # later line 50 ns and a sleep after the one before.
    tm = [[int(x.split("=")[1]) for x in line.split()] for line in runs[0].stdout.splitlines()]
    start = tm[0][0] - 1714564800250050000
    check(len(tm) == 3 and start >= 0 and start % 25 == 0, "time.time() starts at the epoch (%d ns in)" % start,
          runs[0])
    check([b[0] - a[0] for a, b in zip(tm, tm[1:])] == [50 + 250050000] * 2,
          "time.time() then moves by the sleeps and the clock reads", runs[0])
    # The monotonic clock too starts at a fixed value: 100000 s (read
    # right after time.time(), one read later).
    check(all(m - 100000 * 10**9 == t - 1714564800 * 10**9 + 25 for t, m in tm),
          "time.monotonic() starts at 100000 s", runs[0])
    # With no spin costs (--spin-cost 0: reads are free), no start-up
    # offset but whole steps: the first line at the epoch and one sleep,
    # both clocks, but for steps the start-up may be charged where it is
    # found asleep in the kernel (a file read on a loaded machine): it
    # steps aside, and wakes at the world's time (docs/DESIGN.md §2,
    # asleep.cc), a whole step on.
    free = tcs("-q", "-m", "lockstep", "--epoch", "2024-05-01T12:00:00Z", "--spin-cost", "0", "--", PYTHON, "-c",
               script)
    t, m = [int(x.split("=")[1]) for x in free.stdout.split()[:2]]
    check((t - 1714564800250050000) % 1000000 == 0 and m - 100000 * 10**9 == t - 1714564800 * 10**9,
          "--spin-cost 0: time.time() at the epoch and 0.25 s (and whole steps), time.monotonic() at 100000 s as "
          "far on", free)
    # KNOWN FAILURE (issue 36, reported): Python's start-up is charged 2 to
    # 4 clock reads more or fewer from one run to the next (50 to 100 ns),
    # --seed or not, and on a loaded machine now and then a whole step (as
    # above); a C program's reads repeat (below). The contract is that the
    # output repeats.
    check(runs[0].stdout == runs[1].stdout, "two runs with one epoch print the same", runs[1])
    c = [tcs("-q", "-m", "lockstep", "--epoch", "1714564800", prog("clocks")) for _ in range(2)]
    steps = [[line for line in x.stdout.splitlines() if line.startswith("step")] for x in c]
    check(len(steps[0]) == 4 and steps[0] == steps[1], "every clock identical across runs", c[1])
    check("real0=1714564800125050100" in steps[0][0],
          "CLOCK_REALTIME = epoch + virtual time (a sleep and its slack, and four clock reads before)", c[0])


def test_every_clock_reads_virtual_time():
    r = tcs("-q", "-m", "lockstep", "--spin-cost", "0", "--epoch", "2000-01-01T00:00:00Z", prog("clocks"))
    lines = [line for line in r.stdout.splitlines() if line.startswith("step")]
    # Four sleeps, each ending its 50 us of timer slack late.
    expected = [at + (i + 1) * SLACK for i, at in enumerate([125000000, 375000000, 750000000, 1250000000])]
    check(len(lines) == len(expected), "a line after each of the four sleeps", r)
    # TAI runs ahead of UTC by the host's whole seconds of leap (0 where
    # the kernel was never told, 37 since 2017 where it was).
    host_tai = round((time.clock_gettime_ns(time.CLOCK_TAI) - time.time_ns()) / 1e9)
    for line, v in zip(lines, expected):
        for k in range(4):
            check(" mono%d=%d " % (k, v) in line, "monotonic clock %d after the sleeps" % k, r)
        real = 946684800 * 10**9 + v
        check(" real0=%d " % real in line and " real1=%d " % real in line, "realtime clocks", r)
        check(" real2=%d " % (real + host_tai * 10**9) in line, "CLOCK_TAI: realtime + %d s" % host_tai, r)
        check("gettimeofday=%d.%06d" % (real // 10**9, real % 10**9 // 1000) in line, "gettimeofday", r)
        check("time=%d " % (real // 10**9) in line, "time()", r)
        check("timespec_get=%d.%09d" % (real // 10**9, real % 10**9) in line, "timespec_get", r)
        check("ftime=%d.%03d" % (real // 10**9, real % 10**9 // 10**6) in line, "ftime", r)
    v = r.values()
    check(v["backwards"] == "0", "no clock ever goes backwards", r)
    # The process's CPU by every interface, read in this order, each one the
    # same virtual CPU at its own resolution: times() in clock ticks,
    # getrusage in us, clock() in us, the process's CPU-time clock in ns.
    tick = 10**9 // int(v["ticks_per_s"])
    times_ns, rusage, clock_ns = int(v["times_ticks"]) * tick, int(v["rusage_ns"]), int(v["clock_us"]) * 1000
    cpu, thread = int(v["cpu_clock_ns"]), int(v["thread_clock_ns"])
    check(rusage - tick < times_ns <= rusage, "times() is getrusage's, in whole ticks", r)
    # Read one after the other with no wait between, they differ by what
    # tcs charged in between, which is no more than the kernel's CPU around
    # them (kernel_cpu_before_ns to kernel_cpu_ns), and by getrusage's
    # rounding down to microseconds.
    around = int(v["kernel_cpu_ns"]) - int(v["kernel_cpu_before_ns"])
    check(rusage <= clock_ns <= cpu and cpu - rusage <= around + 999,
          "getrusage, clock() and the CPU clock agree: %d ns apart, the kernel's CPU around them %d ns" %
          (cpu - rusage, around), r)
    # Virtual CPU is what the kernel charged less tcs's own: never more.
    kernel = int(v["kernel_cpu_ns"])
    check(0 < cpu <= kernel, "no more CPU than the kernel charged: %d, %d" % (cpu, kernel), r)
    # The thread's CPU clock is its real CPU, tcs's own included (as built,
    # docs/DESIGN.md "Differs"): between the two, read in that order.
    check(cpu <= thread <= kernel, "the thread's CPU clock: %d, between %d and %d" % (thread, cpu, kernel), r)


def test_cpp_chrono_loop():
    r = tcs("-q", "--no-slack", "-m", "lockstep", "--epoch", "1000", prog("chrono_loop"), "200", "5")
    v = r.values()
    check(v["steady_elapsed_ns"] == "1000000000", "200 x sleep_until(+5ms) = 1 s of steady_clock", r)
    # (Read right after steady_clock's: a spin's read, 25 ns with an epoch.)
    check(v["system_now_ns"] == "1001000000025", "system_clock = epoch + virtual time", r)
    check(v["sleep_for_ns"] == "250000000", "sleep_for(250ms) lasts 250 ms", r)


def test_epoch_in_cpu_mode():
    # CLOCK_REALTIME is the epoch plus virtual time in cpu mode too: when
    # the loop ends, its 1 s of sleeps plus the CPU the program had used by
    # then, which is at most what the kernel charged it.
    r = tcs("-q", "--no-slack", "--epoch", "1000", prog("chrono_loop"), "200", "5")
    v = r.values()
    elapsed = int(v["steady_elapsed_ns"])
    check(r.returncode == 0 and 10**9 <= elapsed <= 10**9 + READ + AHEAD,
          "200 sleeps of 5 ms: 1 s, and the last one's return (under 25 us), read up to 20 us ahead: %d ns" %
          elapsed, r)
    beyond = int(v["system_now_ns"]) - 1000 * 10**9 - elapsed
    check(0 <= beyond <= int(v["kernel_cpu_ns"]),
          "system_clock = epoch + 1 s + its CPU so far: %d ns beyond (the kernel charged %s)" %
          (beyond, v["kernel_cpu_ns"]), r)


def test_multiplexer_timeouts_are_virtual():
    r = tcs("-q", "--no-slack", "--spin-cost", "0", "-m", "lockstep", prog("multiplex"))
    v = r.values()
    for name, ms in [("poll", 200), ("ppoll", 300), ("select", 400), ("pselect", 500), ("epoll_wait", 600),
                     ("epoll_pwait", 700)]:
        check(("%s=0 elapsed_ns=%d" % (name, ms * 10**6)) in r.stdout, "%s times out after %d ms" % (name, ms), r)
    check("select=0 elapsed_ns=400000000 isset=0 tv_left_us=0" in r.stdout,
          "select clears the set and reports no time left", r)
    check("ready_poll=1 revents_in=1 elapsed_ns=0" in r.stdout, "a ready fd is reported at once", r)
    check(v["ready_select"] == "1" and v["ready_epoll"] == "1" and v["fd_ok"] == "1", "select/epoll see it", r)


def test_signal_handler_interrupts_waits():
    for mode in ("lockstep", "cpu"):
        r = tcs("-q", "--no-slack", "--spin-cost", "0", "-m", mode, prog("interrupt"), timeout=30)
        check(r.returncode == 0, "interrupt exits 0 (%s)" % mode, r)
        out, v = r.stdout, r.values()
        check("nanosleep=-1 errno=EINTR handled=1" in out, "nanosleep: EINTR", r)
        check("clock_nanosleep=EINTR handled=2" in out, "clock_nanosleep returns EINTR", r)
        check("poll=-1 errno=EINTR handled=3" in out, "poll: EINTR", r)
        check("epoll_wait=-1 errno=EINTR handled=4" in out, "epoll_wait: EINTR", r)
        check("select=-1 errno=EINTR handled=5" in out, "select: EINTR", r)
        check("ppoll=-1 errno=EINTR handled=6" in out, "ppoll with a mask: EINTR", r)
        check("pselect=-1 errno=EINTR handled=7" in out, "pselect with a mask: EINTR", r)
        check("epoll_pwait=-1 errno=EINTR handled=8" in out, "epoll_pwait with a mask: EINTR", r)
        check("epoll_pwait2=-1 errno=EINTR handled=9" in out, "epoll_pwait2 with a mask: EINTR", r)
        check("clock_nanosleep_abs=EINTR handled=10" in out, "an absolute clock_nanosleep: EINTR", r)
        # C11: -1 for a signal, and the time left in rem as nanosleep's.
        check("thrd_sleep=-1 handled=11" in out, "thrd_sleep: -1", r)
        for call in ("nanosleep", "clock_nanosleep", "thrd_sleep"):
            # What is left is what was asked less the time slept: the
            # timer's 50 ms from its arming (in lockstep, arming takes no
            # time) less the virtual time from the arming to the sleep,
            # which in cpu mode is the arming call's return and one clock
            # read (window: the arming itself; each side under 25 us, and
            # each of the window's two reads up to 20 us ahead or behind).
            slept, window = int(v[call + "_slept_ns"]), int(v[call + "_arm_window_ns"])
            if mode == "lockstep":
                check(slept == 50000000 and window == 0, "%s: slept exactly the timer's 50 ms: %d ns" % (call, slept), r)
            else:
                check(0 <= window < READ + 2 * AHEAD and 50000000 - window - READ - 2 * AHEAD <= slept <= 50000000,
                      "%s: slept the timer's 50 ms less the time since it was armed: %d ns (arming took %d)" %
                      (call, slept, window), r)
        check("sleep_left=0" in out, "a later sleep completes", r)
    check("slept_ns=1000000000" in tcs("-q", "--no-slack", "-m", "lockstep", prog("interrupt")).stdout, "exactly 1 s", r)


def test_runtime_fds_survive_closing_every_fd():
    r = tcs("-q", "--no-slack", "-m", "lockstep", prog("close_all"))
    check(r.returncode == 0 and r.values().get("slept_ns") == "2500000000",
          "after closing every fd, sleeps still take exactly their virtual time", r)


if __name__ == "__main__":
    main(globals())
