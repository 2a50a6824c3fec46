"""Lockstep mode and the hooked calls whose results are exact in virtual
time: sleeps, clocks, multiplexer timeouts, EINTR, determinism."""

import os
import re
import shutil
import tempfile
import textwrap

from harness import PYTHON, TCS_RUN, check, main, prog, run, tcs


def test_sleep_30_takes_no_wall_time():
    r = tcs("-m", "lockstep", "--", "sleep", "30", timeout=20)
    check(r.returncode == 0, "sleep 30 should exit 0", r)
    check(r.wall < 1.0, "sleep 30 under lockstep took %.2fs of wall time" % r.wall, r)
    check("30.000 s virtual" in r.stderr, "the summary reports 30 s of virtual time", r)


def test_a_program_that_execs_stays_in_virtual_time():
    # The shell replaces itself with sleep: the new image says HELLO again.
    r = tcs("-m", "lockstep", "--", "sh", "-c", "exec sleep 7", timeout=20)
    check(r.returncode == 0, "exit 0", r)
    check("7.000 s virtual" in r.stderr and r.wall < 2.0, "7 s of virtual time, little wall time", r)


def test_python_sleep_loop_sees_exactly_5s():
    script = textwrap.dedent("""
        import time
        t0 = time.monotonic()
        for _ in range(500):
            time.sleep(0.01)
        print("elapsed=%.9f" % (time.monotonic() - t0))
    """)
    r = tcs("-q", "-m", "lockstep", "--", PYTHON, "-c", script, timeout=30)
    check(r.returncode == 0, "python exits 0", r)
    check(r.values()["elapsed"] == "5.000000000", "500 x time.sleep(0.01) is exactly 5.000 s", r)


def test_a_round_trip_reads_no_cpu_clock():
    # Computation is free in lockstep, so a wait's round trip needs no
    # reading of the controller's CPU clock, a system call that costs 50x a
    # native clock read on some machines: the preload learns what its hooks
    # cost and reads for real only every 64th wait, or after 20 us of
    # computing. strace (which slows everything, so that some estimates do
    # go stale) counts the readings on both sides: a process CPU clock in
    # the controller, a clock id of another process's in the coordinator.
    strace = shutil.which("strace")
    check(strace is not None, "strace is installed (tools/bootstrap.sh test installs it)")
    out = os.path.join(tempfile.mkdtemp(prefix="tcs-test-lockstep-"), "strace.txt")
    r = run([strace, "-f", "-qq", "-e", "trace=clock_gettime", "-o", out, TCS_RUN, "-q", "-m", "lockstep",
             prog("periodic"), "1000", "3", "0"], timeout=120)
    check(r.returncode == 0 and r.values()["loops"] == "3000", "3000 cycles, each a round trip", r)
    calls = [l for l in open(out) if "clock_gettime(" in l]
    cpu = [l for l in calls if re.search(r"clock_gettime\((CLOCK_(PROCESS|THREAD)_CPUTIME_ID|0x[0-9a-f]+|-\d+)", l)]
    print("  %d CPU-clock readings in 3000 round trips (%d clock_gettime system calls in all)" % (len(cpu), len(calls)))
    check(len(cpu) < 3000 / 4, "fewer than one CPU-clock reading in four round trips: %d" % len(cpu))


def test_same_epoch_same_timestamps():
    script = "import time\nfor i in range(3):\n    time.sleep(0.25)\n    print('t=%d' % time.time_ns())\n"
    runs = [tcs("-q", "-m", "lockstep", "--epoch", "2024-05-01T12:00:00Z", "--", PYTHON, "-c", script)
            for _ in range(2)]
    check(runs[0].stdout == runs[1].stdout, "two runs with one epoch print the same", runs[1])
    check(runs[0].stdout.split()[0] == "t=1714564800250000000", "time.time() starts at the epoch", runs[0])
    c = [tcs("-q", "-m", "lockstep", "--epoch", "1714564800", prog("clocks")) for _ in range(2)]
    steps = [[line for line in x.stdout.splitlines() if line.startswith("step")] for x in c]
    check(len(steps[0]) == 4 and steps[0] == steps[1], "every clock identical across runs", c[1])
    check("real0=1714564800125000000" in steps[0][0], "CLOCK_REALTIME = epoch + virtual time", c[0])


def test_every_clock_reads_virtual_time():
    r = tcs("-q", "-m", "lockstep", "--epoch", "2000-01-01T00:00:00Z", prog("clocks"))
    lines = [line for line in r.stdout.splitlines() if line.startswith("step")]
    expected = [125000000, 375000000, 750000000, 1250000000]
    for line, v in zip(lines, expected):
        for k in range(4):
            check(" mono%d=%d " % (k, v) in line, "monotonic clock %d after the sleeps" % k, r)
        real = 946684800 * 10**9 + v
        check(" real0=%d " % real in line and " real1=%d " % real in line, "realtime clocks", r)
        check("gettimeofday=%d.%06d" % (real // 10**9, real % 10**9 // 1000) in line, "gettimeofday", r)
        check("time=%d " % (real // 10**9) in line, "time()", r)
        check("timespec_get=%d.%09d" % (real // 10**9, real % 10**9) in line, "timespec_get", r)
        check("ftime=%d.%03d" % (real // 10**9, real % 10**9 // 10**6) in line, "ftime", r)
    check(r.values()["backwards"] == "0", "no clock ever goes backwards", r)


def test_cpp_chrono_loop():
    r = tcs("-q", "-m", "lockstep", "--epoch", "1000", prog("chrono_loop"), "200", "5")
    v = r.values()
    check(v["steady_elapsed_ns"] == "1000000000", "200 x sleep_until(+5ms) = 1 s of steady_clock", r)
    check(v["system_now_ns"] == "1001000000000", "system_clock = epoch + virtual time", r)
    check(v["sleep_for_ns"] == "250000000", "sleep_for(250ms) lasts 250 ms", r)


def test_multiplexer_timeouts_are_virtual():
    r = tcs("-q", "-m", "lockstep", prog("multiplex"))
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
        r = tcs("-q", "-m", mode, prog("interrupt"), timeout=30)
        check(r.returncode == 0, "interrupt exits 0 (%s)" % mode, r)
        out = r.stdout
        check("nanosleep=-1 errno=EINTR rem_large=1 handled=1" in out, "nanosleep: EINTR and time left", r)
        check("clock_nanosleep=EINTR handled=2" in out, "clock_nanosleep returns EINTR", r)
        check("poll=-1 errno=EINTR handled=3" in out, "poll: EINTR", r)
        check("epoll_wait=-1 errno=EINTR handled=4" in out, "epoll_wait: EINTR", r)
        check("select=-1 errno=EINTR handled=5" in out, "select: EINTR", r)
        check("sleep_left=0" in out, "a later sleep completes", r)
    check("slept_ns=1000000000" in tcs("-q", "-m", "lockstep", prog("interrupt")).stdout, "exactly 1 s", r)


def test_runtime_fds_survive_closing_every_fd():
    r = tcs("-q", "-m", "lockstep", prog("close_all"))
    check(r.returncode == 0 and r.values().get("slept_ns") == "2500000000",
          "after closing every fd, sleeps still take exactly their virtual time", r)


if __name__ == "__main__":
    main(globals())
