"""How a run starts and ends: exit statuses pass through, signals end runs
cleanly, no process is ever left behind (stopped or not), programs tcs
cannot serve are refused, and bad command lines get one clear line."""

import os
import signal
import subprocess
import time

from harness import (PYTHON, TCS_RUN, assert_nothing_left, calibrate, check, main, periodic_on_time, prog, run, session_processes,
                     start, tcs)


def test_exit_status_passes_through():
    r = tcs("-q", prog("exit_with"), "3")
    check(r.returncode == 3, "exit 3 passes through", r)
    r = tcs(prog("exit_with"), "segv")
    check(r.returncode == 139, "death by SIGSEGV is 128+11", r)
    check("killed by SIGSEGV" in r.stderr, "the summary says how it ended", r)
    check(tcs("-q", "-m", "lockstep", prog("exit_with"), "abort").returncode == 134, "SIGABRT is 134")


def test_duration_ends_the_run_with_0():
    r = tcs("-d", "2s", "--", "sleep", "30", timeout=20)
    check(r.returncode == 0, "--duration ending the run exits 0", r)
    check("2.000 s virtual" in r.stderr and "ended with the run" in r.stderr, "the summary says so", r)
    r = tcs("-q", "-m", "lockstep", "-d", "250ms", prog("periodic"), "1000", "100", "0", timeout=20)
    check(r.returncode == 0, "a periodic loop stopped by --duration exits 0", r)


def test_a_program_asleep_at_the_end_reads_the_ends_time():
    # Asleep from 0.9 s to 1.2 s when a 1 s run ends: woken by SIGTERM at
    # 1 s, where its clocks go on from (they read 0.9 s here once: the
    # page still held the slice before its sleep).
    script = """
import signal, sys, time
def done(*_):
    print("end_ns=%d" % (time.monotonic_ns() - 100000 * 10**9))
    sys.exit(0)
signal.signal(signal.SIGTERM, done)
while True:
    time.sleep(0.3 - time.monotonic() % 0.3)
"""
    for mode in ("lockstep", "cpu"):
        r = tcs("-m", mode, "--epoch", "0", "-d", "1s", "--", PYTHON, "-c", script, timeout=30)
        v = r.values()
        check(r.returncode == 0 and "end_ns" in v, "%s: the handler prints" % mode, r)
        end = int(v["end_ns"])
        print("  %-8s the handler read %.9f s" % (mode, end / 1e9))
        # Lockstep: the handler's read follows the wake, at no cost; cpu
        # mode: after the handler's own CPU (well under 50 ms).
        ok = end == 10**9 if mode == "lockstep" else 10**9 <= end <= 10**9 + 50 * 10**6
        check(ok, "%s: a program asleep at the end reads the end's time, 1 s: %d ns" % (mode, end), r)


def signal_run(sig, mode):
    p = start([TCS_RUN, "-q", "-m", mode, prog("periodic"), "1000", "1000000", "20000"])
    time.sleep(0.5)
    check(p.poll() is None, "the run is still going before the signal")
    os.kill(p.pid, sig)
    try:
        p.communicate(timeout=10)
    except Exception:
        os.killpg(p.pid, signal.SIGKILL)
        raise
    assert_nothing_left(p.pid)
    return p.returncode


def test_sigterm_and_sigint_end_the_run_cleanly():
    for mode in ("cpu", "lockstep"):
        check(signal_run(signal.SIGTERM, mode) == 143, "SIGTERM to tcs-run: exit 143, nothing left (%s)" % mode)
        check(signal_run(signal.SIGINT, mode) == 130, "SIGINT to tcs-run: exit 130, nothing left (%s)" % mode)
    # tcs-run(1): SIGHUP and SIGQUIT end it the same way.
    check(signal_run(signal.SIGHUP, "cpu") == 129, "SIGHUP to tcs-run: exit 129, nothing left")
    check(signal_run(signal.SIGQUIT, "cpu") == 131, "SIGQUIT to tcs-run: exit 131, nothing left")


def stubborn_run():
    """tcs-run over a shell that ignores SIGTERM and sleeps on."""
    p = start([TCS_RUN, "-q", "--", "sh", "-c", "trap '' TERM; while :; do sleep 0.01; done"])
    time.sleep(0.5)
    check(p.poll() is None, "the run is still going before the signal")
    return p


def test_a_program_that_ignores_sigterm_is_killed_after_the_grace():
    # tcs-run(1): the programs get SIGTERM, and SIGKILL if still there 2 s
    # (wall time) later. The lower bound is the contract; the upper one
    # only says it does not hang.
    p = stubborn_run()
    t0 = time.monotonic()
    p.send_signal(signal.SIGTERM)
    p.communicate(timeout=20)
    took = time.monotonic() - t0
    assert_nothing_left(p.pid)
    print("  a program ignoring SIGTERM was killed %.2f s after it" % took)
    check(p.returncode == 143 and 2.0 <= took < 10, "exit 143, after the 2 s grace: %.2f s" % took)


def test_a_second_signal_kills_at_once():
    # A second signal during the grace: SIGKILL at once, not 2 s later.
    p = stubborn_run()
    t0 = time.monotonic()
    p.send_signal(signal.SIGTERM)
    time.sleep(0.2)
    p.send_signal(signal.SIGTERM)
    p.communicate(timeout=20)
    took = time.monotonic() - t0
    assert_nothing_left(p.pid)
    print("  with a second signal 0.2 s after the first, it ended %.2f s after the first" % took)
    check(p.returncode == 143 and took < 2.0, "ended before the grace was over: %.2f s" % took)


def test_controller_dies_with_a_killed_coordinator():
    for mode in ("cpu", "lockstep"):
        p = start([TCS_RUN, "-q", "-m", mode, prog("periodic"), "1000", "1000000", "20000"])
        time.sleep(0.5)
        # Both running before the kill: else there is nothing to outlive it.
        running = [cmd for _, state, cmd in session_processes(p.pid) if state not in "ZX"]
        check(p.poll() is None and running.count("tcs-run") == 1 and running.count("periodic") == 1,
              "%s: tcs-run and its controller run before the SIGKILL: %s" % (mode, running))
        os.kill(p.pid, signal.SIGKILL)
        # The controller has tcs-run's stdout and stderr: communicate()
        # returns at their end, when every process holding them has ended
        # (a controller dies of the SIGKILL its parent's death sends it,
        # stopped or not). So it has ended by then: what may be left is
        # the last of an exit, the harness's reap allowance.
        p.communicate(timeout=10)
        check(p.returncode == -signal.SIGKILL, "%s: tcs-run was killed" % mode)
        assert_nothing_left(p.pid)


def test_static_binary_is_refused():
    r = tcs(prog("static_hello"))
    check(r.returncode == 2, "a static binary is refused with exit 2", r)
    check("statically linked" in r.stderr and "hello" not in r.stdout, "and not run in real time", r)
    check(len(r.stderr.strip().splitlines()) == 1, "with one line", r)


def test_bad_command_lines():
    cases = [
        (["--", "no-such-program-tcs"], "command not found"),
        (["--mode", "fast", "true"], "not a mode"),
        (["-d", "ten", "true"], "not a duration"),
        (["-d", "10parsecs", "true"], "unknown unit"),
        (["--cpu-scale", "0", "true"], "not a positive number"),
        (["--epoch", "2024-02-30T00:00:00Z", "true"], "not an epoch"),
        (["--bogus", "true"], "unknown option"),
        (["-d"], "needs a value"),
        ([], "no PROGRAM"),
        (["/etc/passwd"], "not executable"),
        (["/tmp"], "is a directory"),
    ]
    for args, message in cases:
        r = tcs(*args)
        check(r.returncode == 2, "tcs-run %s exits 2" % " ".join(args), r)
        check(message in r.stderr and r.stderr.startswith("tcs-run: "), "the error names the cause", r)
        check(r.stderr.count("\n") <= 2, "one line (and a hint)", r)


def test_help_and_version():
    r = tcs("--help")
    check(r.returncode == 0 and r.stdout.startswith("Usage: tcs-run") and "--cpu-scale" in r.stdout, "help", r)
    r = tcs("--version")
    check(r.returncode == 0 and r.stdout.startswith("tcs-run "), "version", r)


def test_without_sched_fifo_it_warns_once_and_still_works():
    # Root without CAP_SYS_NICE cannot use SCHED_FIFO, as an ordinary user.
    nofifo = ["setpriv", "--bounding-set=-sys_nice", "--inh-caps=-sys_nice", "--", TCS_RUN]
    r = run(nofifo + ["-m", "lockstep", "--", "sleep", "3"])
    check(r.returncode == 0 and "3.000 s virtual" in r.stderr, "lockstep still exact", r)
    check(r.stderr.count("SCHED_FIFO not permitted") == 1, "one clear warning", r)
    check("normal scheduling" in r.stderr, "the summary says how it ran", r)
    r = run(nofifo + ["-q", prog("periodic"), "1000", "1", "0"])
    check(r.returncode == 0, "cpu mode works without SCHED_FIFO", r)
    periodic_on_time(r.values(), 1000, 1, "a 1 kHz loop without SCHED_FIFO", r)


def test_without_the_tsc_it_warns_once_and_clocks_stay_exact():
    # As on a machine whose CPU has no invariant TSC: the vDSO's clock
    # serves the estimates instead, and says so once, with the reason.
    r = tcs(prog("clocks"), env={"TCS_NO_TSC": "1"})
    check(r.returncode == 0 and r.values()["backwards"] == "0", "no clock goes back", r)
    check(r.stderr.count("warning: the TSC is not to be used (TCS_NO_TSC)") == 1, "one warning that names why", r)
    check("vDSO clock" in r.stderr, "and says what serves instead", r)
    r = tcs("-q", prog("periodic"), "1000", "1", "300us", env={"TCS_NO_TSC": "1"})
    check(r.returncode == 0, "a 1 kHz loop runs without the TSC", r)
    periodic_on_time(r.values(), 1000, 1, "a 1 kHz loop without the TSC", r)
    # Where the CPU says its TSC is invariant, the TSC serves without a word,
    # whatever the kernel's clocksource (kvm-clock on some VMs).
    flags = next((l for l in open("/proc/cpuinfo") if l.startswith("flags")), "").split()
    if "TCS_NO_TSC" not in os.environ and "constant_tsc" in flags and "nonstop_tsc" in flags:
        r = tcs("-q", prog("periodic"), "1000", "1", "0")
        check(r.returncode == 0 and "TSC" not in r.stderr, "no warning with an invariant TSC", r)



def test_progress_line_on_a_terminal():
    import pty
    master, slave = pty.openpty()
    # About a second of wall time: several progress ticks.
    p = subprocess.Popen([TCS_RUN, "--", prog("periodic"), "1000", "2", str(calibrate() // 2)],
                         stdout=subprocess.DEVNULL, stderr=slave, stdin=subprocess.DEVNULL, start_new_session=True)
    os.close(slave)
    out = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:
            break
        if not chunk:
            break
        out += chunk
    p.wait(timeout=60)
    os.close(master)
    assert_nothing_left(p.pid)
    text = out.decode(errors="replace")
    check(p.returncode == 0, "the run succeeds: " + text)
    check("\r\x1b[Ktcs-run: " in text and " virtual, " in text, "a progress line is drawn: " + text)
    last = text.rstrip().splitlines()[-1]
    check(last.startswith("tcs-run:   ") and "periodic waits" in last, "the summary comes last: " + last)
    r = tcs("-m", "lockstep", "--", "sleep", "1")
    check("\x1b[K" not in r.stderr, "no progress line when stderr is not a terminal", r)



def test_child_processes_run_quietly_in_virtual_time():
    r = tcs("--", "sh", "-c", "sleep 0.1; sleep 0.1; echo done", timeout=30)
    check(r.returncode == 0 and r.stdout.strip() == "done", "a shell controller with children runs", r)
    check("runs in real time" not in r.stderr, "no child falls back to real time", r)
    check("and 2 child processes" in r.stderr, "the summary counts its two children", r)


if __name__ == "__main__":
    main(globals())
