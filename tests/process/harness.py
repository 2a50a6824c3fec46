"""Process-test harness: runs real programs under tcs-run with a timeout,
in a session of their own, and fails a test that leaves any process behind
(stopped or not). Each test file is a list of test_* functions; main() runs
them and ends with the line 'N passed, N failed, N skipped'."""

import contextlib
import csv
import ctypes
import io
import itertools
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import traceback

from sessions import session_processes  # noqa: F401 (tests import it from here)

TCS_RUN = os.environ.get("TCS_RUN", "tcs-run")
TCS_TRACE = os.environ.get("TCS_TRACE", "tcs-trace")
PROGRAMS = os.environ.get("TCS_PROGRAMS", ".")
PYTHON = os.environ.get("TCS_PYTHON", sys.executable)


def prog(name):
    return os.path.join(PROGRAMS, name)


class Result:
    def __init__(self, args, returncode, stdout, stderr, wall):
        self.args, self.returncode, self.stdout, self.stderr, self.wall = args, returncode, stdout, stderr, wall

    def values(self):
        """key=value pairs printed by the program (several per line allowed)."""
        return dict(re.findall(r"([A-Za-z_][\w]*)=(\S+)", self.stdout))

    def __repr__(self):
        return "exit %s after %.2fs\n--- stdout\n%s--- stderr\n%s" % (
            self.returncode, self.wall, self.stdout[-3000:], self.stderr[-3000:])


def demote(sid):
    """Every process of the session to normal scheduling: a SCHED_FIFO
    process that spins in the kernel outlives SIGKILL until it may be
    preempted (seen while debugging a hang), and would starve what runs
    next on its core."""
    for pid, _, _ in session_processes(sid):
        try:
            os.sched_setscheduler(pid, os.SCHED_OTHER, os.sched_param(0))
        except OSError:
            pass


def assert_nothing_left(sid, grace=2.0):
    """Every process of the session must be gone (zombies of ours aside).
    tcs-run's end kills what is left of its run at once (and the harness's
    processes die with it: PR_SET_PDEATHSIG), so nothing should remain; the
    grace is only the time a loaded machine may take to let them exit, and
    a process still there after it (stopped ones above all) is left behind."""
    deadline = time.monotonic() + grace
    while True:
        left = [p for p in session_processes(sid) if p[1] != "Z"]
        if not left:
            return
        if time.monotonic() > deadline:
            demote(sid)
            for pid, _, _ in left:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            raise AssertionError("processes left behind (state T = stopped): %s" % left)
        time.sleep(0.02)


# How far a cpu-mode clock read may run ahead of (or behind) the kernel's
# CPU: it is an estimate from the TSC or the vDSO clock whose anchor is read
# again after 20 us (libtcs_preload/cpu_estimate.c, tick_resync).
AHEAD = 20000
# The most one call costs the program, its hook included, where a program
# does not read that cost itself: a ceiling chosen at about 8x the slowest
# CPU-clock system call measured (0.2 to 1.7 us on the machines seen, 3 us
# in the slowclock setup).
READ = 25000
# Linux's timer slack for a normal thread: a timed wait ends this late
# (docs/DESIGN.md §2), unless the run is --no-slack.
SLACK = 50000


_controller_core = []


def controller_core():
    """The core a lone controller runs on under tcs-run: beside the
    coordinator's (the last allowed) where SCHED_FIFO and a second core
    allow, else on it (docs/DESIGN.md, Lanes). Asked of tcs-run once, by a
    probe that reports the cores it ran on."""
    if not _controller_core:
        probe = run([TCS_RUN, "-q", prog("periodic"), 1000, "0.01", 0])
        seen = probe.values().get("cores_seen", "0")
        check(probe.returncode == 0 and seen != "0", "the core probe runs under tcs-run", probe)
        _controller_core.append(first_core(seen))
    return _controller_core[0]


PR_SET_PDEATHSIG = 1


def start(args, env=None, core=None):
    """args started in a session of their own (on that core, if given)."""
    full_env = dict(os.environ)
    full_env.update(env or {})

    def pre():
        # Killed with this harness, should meson's own timeout end it: its
        # own session is out of reach of the signal meson sends.
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
        if core is not None:
            os.sched_setaffinity(0, {core})
    return subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                            start_new_session=True, env=full_env, text=True, preexec_fn=pre)


def finish(p, timeout, t0):
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        demote(p.pid)
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        assert_nothing_left(p.pid)
        raise AssertionError("timed out after %ss: %s\n%s%s" % (timeout, p.args, out[-2000:], err[-2000:]))
    result = Result(p.args, p.returncode, out, err, time.monotonic() - t0)
    assert_nothing_left(p.pid)
    # The coordinator's transition table (coordinator/controller_state.h)
    # held for every controller of every run the tests make.
    check("is not a move it can make" not in err, "no controller made a move its state forbids", result)
    return result


def run(args, timeout=60, env=None, core=None):
    t0 = time.monotonic()
    return finish(start([str(a) for a in args], env, core), timeout, t0)


def native(args, timeout=60, core=None):
    """A program run natively on a core tcs-run runs controllers on (or the
    one given: where the tcs run it is compared with ran). A native run
    compared with a tcs run must use the same core: the cores of a shared
    virtual machine are not equally fast (0.7 % apart here)."""
    return run(args, timeout=timeout, core=controller_core() if core is None else core)


def first_core(cores_seen):
    """The lowest core in a mask of cores (periodic's cores_seen)."""
    mask = int(cores_seen)
    return (mask & -mask).bit_length() - 1


def tcs(*args, timeout=60, env=None):
    """tcs-run ARGS...; quiet unless the test asks for the summary."""
    return run([TCS_RUN] + list(args), timeout=timeout, env=env)


def run_balancer(mode, scenario, argv, args=(), options=(), timeout=120):
    """A balancing example (argv, then args) under tcs-run in mode on
    scenario: it must end and report its verdict (balanced=...); its
    key=value pairs and the result. Prints its verdict line."""
    r = tcs("-q", "-m", mode, *options, "-w", scenario, "--", *argv, *args, timeout=timeout)
    v = r.values()
    check(r.returncode == 0 and "balanced" in v, "%s: %s %s runs and reports" %
          (mode, os.path.basename(argv[-1]), " ".join(args)), r)
    print("  %-8s %-36s %s" % (mode, " ".join(tuple(options) + tuple(args)), r.stdout.splitlines()[0]))
    return v, r


def trace_rows(path, topic):
    """One topic of a trace (tcs-trace export --format csv) as dicts of its
    columns."""
    e = run([TCS_TRACE, "export", path, "--format", "csv", "--topic", topic])
    check(e.returncode == 0, "tcs-trace export %s" % topic, e)
    return list(csv.DictReader(io.StringIO(e.stdout)))


MCAP_CHECK = os.environ.get("TCS_MCAP_CHECK", "tests/mcap/check.mjs")


def read_trace(path, complete=True):
    """A trace as the ecosystem's reference readers read it (tests/mcap/
    check.mjs: @mcap/core, every message decoded as Foxglove decodes it):
    its {messages, channels, schemas, topics: {topic: count}, truncated}.
    complete: the file must have its footer. Node.js and the readers
    (npm ci in tests/mcap) are what the check needs: missing()."""
    need_tool("node", "nodejs")
    readers = os.path.join(os.path.dirname(MCAP_CHECK), "node_modules")
    for package in ("@mcap/core", "@foxglove/rosmsg", "@foxglove/rosmsg2-serialization", "@foxglove/wasm-zstd"):
        if not os.path.isdir(os.path.join(readers, package)):
            missing("the MCAP reader's %s is not in %s" % (package, readers),
                    "npm ci --prefix %s (tools/bootstrap.sh test runs it)" % os.path.dirname(MCAP_CHECK))
    r = run(["node", MCAP_CHECK] + (["--complete"] if complete else []) + [path], timeout=120)
    check(r.returncode == 0, "the official MCAP reader reads %s" % path, r)
    return json.loads(r.stdout.strip().splitlines()[-1])


def check(cond, what, result=None):
    if not cond:
        raise AssertionError(what + ("\n" + repr(result) if result is not None else ""))


@contextlib.contextmanager
def scenario_file(text):
    """A scenario written to a temporary file for the length of a with block."""
    fd, path = tempfile.mkstemp(suffix=".toml", prefix="tcs-test-")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    try:
        yield path
    finally:
        os.unlink(path)


def calibrate():
    """Rounds of work() per millisecond of CPU, measured natively."""
    return int(native([prog("calibrate")]).stdout.strip())


def program_reports(stdout, first):
    """The reports of several test programs sharing one stdout, each
    printed in one write at its end as key=value lines starting with key
    first, as dicts in the order they ended."""
    reports = []
    for block in stdout.split(first + "=")[1:]:
        lines = itertools.takewhile(lambda line: "=" in line and " " not in line, (first + "=" + block).splitlines())
        reports.append(dict(line.split("=", 1) for line in lines))
    return reports


def periodic_reports(stdout):
    """tests/programs/periodic's reports (program_reports)."""
    return program_reports(stdout, "asked_hz")


def periodic_on_time(v, hz, seconds, what, result=None, slack=SLACK):
    """tests/programs/periodic HZ SECONDS with work that fits its period:
    misses only where the kernel's CPU explains them (pause_misses), ending
    no later than its last round's release and slack (or its start, if
    later) and the CPU the kernel charged that round, and
    unless it explains lateness (pause_misses, crossed_waits), exactly
    HZ * SECONDS loops ending at the last one's release and its timer slack
    (slack: SLACK, or 0 for a --no-slack run) plus what followed it: the CPU from the last wait's return on, by the kernel's clock
    (tail_kernel_cpu_ns), with the return itself before that read (READ),
    and what the kernel charged the program within the last wait's call
    beyond the least such call (last_ and least_wait_kernel_cpu_ns), up to
    one stop's cost (stop_cost(), outside tcs): the kernel's work for a
    stop falling after the hook's mark and before the loop's first read,
    where the program cannot see it, of which tcs leaves out only the
    machine's mean (26 us at the median here, 84 us at most in 60 loops;
    none of it needed by the loop's end). Beyond that bound, CPU charged
    within the wait's call is tcs's fault: the hook's own return charged
    as the program's (test_cores checks each slice in the trace). Where a
    loop without work does not read it: the wait's return and periodic's
    two reads after it (two calls, READ each). And what the last read
    runs ahead (AHEAD)."""
    loops, elapsed = int(v.get("loops", 0)), float(v.get("elapsed_s", 0))
    misses, pauses = int(v.get("misses", 1 << 30)), int(v.get("pause_misses", -1))
    check(misses <= pauses, "%s: misses only where the kernel's CPU explains them (%d, %d)" % (what, misses, pauses),
          result)
    if pauses == 0 and v.get("crossed_waits") == "0":
        tail = int(v.get("tail_kernel_cpu_ns", -1))
        paused = int(v.get("last_wait_kernel_cpu_ns", 0)) - int(v.get("least_wait_kernel_cpu_ns", 0))
        paused = min(paused, stop_cost()) if paused > 0 else 0
        after = READ + tail + paused if tail >= 0 else 2 * READ
        end = seconds + slack / 1e9
        check(loops == round(hz * seconds) and end <= elapsed <= end + (after + AHEAD) / 1e9,
              "%s: %d loops in %.9f s" % (what, loops, elapsed), result)
    else:
        # Late somewhere, as the kernel's CPU explains: still bounded. The
        # last round began at last_round_start_ns (before the end, an
        # estimated read: AHEAD either way) and waited for its release and
        # its slack, or for nothing; beyond the later of those two, only its
        # CPU, which the kernel charged it from just before that read on
        # (last_round_kernel_cpu_ns; a loop without work reads none of
        # these, and has no pause to explain).
        start, cpu = int(v.get("last_round_start_ns", -1)), int(v.get("last_round_kernel_cpu_ns", -1))
        check(start >= 0 and cpu >= 0, "%s: late, and periodic read its last round's CPU" % what, result)
        most = (max(start, loops * 1e9 / hz + slack) + cpu + 2 * AHEAD) / 1e9
        check(loops <= round(hz * seconds) and seconds + slack / 1e9 <= elapsed <= most,
              "%s: %d loops in %.9f s (at most %.9f s)" % (what, loops, elapsed, most),
              result)


_stop_cost = []


def stop_cost():
    """The most a stop and its continuation cost a process here, by
    bench/stop_cost (outside tcs): twice the larger median of a stop from
    another core and from its own (continuing costs less than stopping:
    1 to 12 us against 4 to 90). tcs leaves that cost out of what it
    charges (docs/DESIGN.md, "Preemption and accounting"). Measured once."""
    if not _stop_cost:
        program = os.path.join(os.environ.get("TCS_BUILD_ROOT", "build"), "bench", "stop_cost")
        medians = []
        for same_core in ([], [max(os.sched_getaffinity(0))]):
            m = run([program, 100] + same_core)
            check(m.returncode == 0, "bench/stop_cost measures a stop", m)
            medians.append(int(m.values()["stop_cost_median_ns"]))
        _stop_cost.append(2 * max(medians))
    return _stop_cost[0]


def charged_as_the_kernel_says(v, scale, result=None):
    """burn's figures (tests/programs/burn.c) against the contract: virtual
    time is the CPU the kernel charged the program, times the scale: no
    less than the kernel's CPU read inside the virtual clocks' span, less
    what its stops cost (each is a voluntary switch, and burn makes no
    other), no more than read around it (so tcs's own clock reads, and a
    pause of the machine between two reads, fall on the right side of each
    bound), give or take what an estimated read runs ahead (AHEAD)."""
    outer, inner, virtual, ahead = int(v["kernel_cpu_ns"]), int(v["kernel_inner_cpu_ns"]), int(v["monotonic_ns"]), AHEAD
    stops = int(v["voluntary_switches"])
    left_out = stops * stop_cost() if stops else 0
    check((inner - left_out - ahead) * scale <= virtual <= (outer + ahead) * scale,
          "virtual time %d ns: the kernel's %d ns (inside, less %d stops' %d ns) to %d ns (around) of CPU x %g "
          "(+- %d ns)" % (virtual, inner, stops, left_out, outer, scale, ahead), result)


def paired_runs(n, under_tcs, natively, core_of):
    """n tcs runs and n native runs of the same work, interleaved, the
    order of each pair alternating (so that neither side always follows
    the other), each native run on the core its tcs run used (core_of of
    the tcs run's values; the first pair goes tcs first to learn it).
    under_tcs() and natively(core) return the runs' values."""
    tcs_runs, native_runs, core = [], [], None
    for i in range(n):
        if i % 2:
            native_runs.append(natively(core))
            tcs_runs.append(under_tcs())
        else:
            tcs_runs.append(under_tcs())
            native_runs.append(natively(core_of(tcs_runs[-1])))
        core = core_of(tcs_runs[-1])
    return tcs_runs, native_runs


def costs_as_natively(under_tcs, natively, what):
    """The same work's CPU under tcs and natively, n runs each (paired_runs).
    If tcs adds nothing to what the work costs
    (and takes nothing from it), both are draws from one distribution, and
    their ranges overlap: all n under tcs above every native one, or all
    below, has probability 2 n!n!/(2n)! (1 in 24310 for 9). No tolerance of
    its own: the machine's scatter, measured in the same test, is the
    bound; a difference tcs makes shows once it is larger than that."""
    lo, hi = min(natively), max(natively)
    print("  %s: %.4g to %.4g under tcs, %.4g to %.4g natively (%d runs each)" %
          (what, min(under_tcs), max(under_tcs), lo, hi, len(natively)))
    check(max(under_tcs) >= lo and min(under_tcs) <= hi,
          "%s: every one of %d runs under tcs (%.6g to %.6g) is outside the native runs' %.6g to %.6g" %
          (what, len(under_tcs), min(under_tcs), max(under_tcs), lo, hi))


class Skip(Exception):
    """What a test could not check here, and why."""


def skip(reason):
    """Ends the test as skipped: the check it makes needs what this machine
    lacks. A weaker check in its place is no pass of the stronger one."""
    raise Skip(reason)


def under_ci():
    """Whether this is a CI run: CI set, as CI services set it (CI=true;
    .ci/run sets it too), to anything but empty, 0 or false."""
    return os.environ.get("CI", "").lower() not in ("", "0", "false")


def missing(what, how):
    """Something a test needs is absent here (a tool, a folder of files):
    under CI a failure naming it and how to get it, since a CI machine that
    lacks it would otherwise go green without the check; elsewhere a skip,
    which tools/bootstrap.sh lists with this reason."""
    reason = "%s: %s" % (what, how)
    if under_ci():
        raise AssertionError("%s (a failure, not a skip, under CI=%s)" % (reason, os.environ["CI"]))
    skip(reason)


def need_tool(program, package):
    """The path of a program a test runs, from the Debian package that has
    it; where it is not installed, missing() (a CI failure, else a skip)."""
    path = shutil.which(program)
    if path is None:
        missing("%s is not installed" % program,
                "apt-get install %s (tools/bootstrap.sh test installs it)" % package)
    return path


# Meson's exit status for a test that was skipped as a whole.
EXIT_SKIP = 77


def main(namespace):
    """Runs the file's test_ functions (or those named on the command line),
    one line each: ok, FAILED with the traceback, or SKIP with the reason
    (tools/test_summary.py counts these and lists each skip at the end of
    tools/bootstrap.sh test). Exit 1 if any failed, 77 if
    every one was skipped."""
    tests = [(n, f) for n, f in namespace.items() if n.startswith("test_") and callable(f)]
    only = sys.argv[1:]
    passed = failed = skipped = 0
    for name, fn in tests:
        if only and name not in only:
            continue
        t0 = time.monotonic()
        try:
            fn()
            passed += 1
            print("ok     %-48s %6.2fs" % (name, time.monotonic() - t0), flush=True)
        except Skip as why:
            skipped += 1
            # One line, the reason last: tools/test_summary.py reads it.
            print("SKIP   %-48s %s" % (name, " ".join(str(why).split())), flush=True)
        except Exception:
            failed += 1
            print("FAILED %-48s %6.2fs" % (name, time.monotonic() - t0), flush=True)
            traceback.print_exc(file=sys.stdout)
    print("%d passed, %d failed, %d skipped" % (passed, failed, skipped))
    sys.exit(1 if failed else EXIT_SKIP if skipped and not passed else 0)
