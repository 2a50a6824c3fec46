#!/usr/bin/env python3
"""run_corpus.py: runs the idiom corpus (cases.py) natively and under
tcs-run (cpu and lockstep mode), and judges each tcs run by the contract
(docs/DESIGN.md §10) and against the native run of the same case:
  hang     no end within --timeout s of wall time (the session is killed)
  crash    killed by a signal, or tcs-run itself failed
  wrong    the program's own checks failed (first_failure says which), or
           it completed another number of calls than natively, or a device
           was absent under tcs, or its timer slack differs from native,
           or in lockstep a CALL's wait lasted longer than its slack and
           the reads around it (LOCKSTEP_OVER)
  warning  tcs printed something other than its summary: a call that tcs
           cannot keep in virtual time is a defect, not a warning
  leftover a process of the run was still there after it ended
  not run  --budget's wall time was spent before it started
A native run is judged by the program's checks alone (a device case
natively only by its exit and report: /dev/tcs is absent there).
Prints `FAIL mode context call interrupted: kind: reason` per failing
run, a tally of the kinds, and last `N passed, M failed`; exit 1 if any
failed. Every run is a session of its own, killed whole (SIGCONT, then
SIGKILL to each of its processes) on timeout or if anything outlives it.
--results keeps each run's verdict as it comes, so a long run that is
stopped resumes where it was.

The program: --program, else $TCS_PROGRAMS/idioms, else
build/tests/programs/idioms; tcs-run: --tcs-run, else $TCS_RUN, else
build/tools/tcs-run."""

import argparse
import collections
import ctypes
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "process"))
import cases as corpus  # noqa: E402
from sessions import session_processes  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(HERE))
IDIOMS_PY = os.path.join(HERE, "idioms.py")

# Wall-clock bound of one run: a case takes well under a second natively
# and under tcs, but for the lockstep ones whose flow loops over clock or
# timer reads, each stopped as a spin (seen: 5.5 s); 20 s is a hang.
TIMEOUT = 20
MODES = ("cpu", "lockstep")

# What tcs-run prints at the end of every run (cli/run_report.cc): its
# first line and the indented ones under it. Any other line from tcs-run
# or the preload ("tcs: ...") is a warning, and so a failure.
SUMMARY = re.compile(r"^tcs-run: \S+ \S+ virtual in |^tcs-run:   ")
FROM_TCS = re.compile(r"^(tcs|tcs-run):|libtcs_preload")
# A summary line that says a process never loaded the preload: a process
# of the run outside virtual time.
OUTSIDE = re.compile(r"never loaded libtcs_preload")

# How much longer than it asked a CALL's wait may last in lockstep, where
# computation is free (tests/README.md, "How timing is checked"): its
# thread's timer slack (50 us, docs/DESIGN.md §2), and three calls at 25 us
# each (READ: the clock read before it, the one after, and the one its
# deadline was computed from). Only the CALL's waits, the handlers that
# may interrupt them being the wake signals' (which only count): one
# restarted after such a signal with a timeout in whole ms, rounded up,
# is measured from the end its restart asked for (idioms' waited_asked).
# The interrupted flow's waits last as long as the handlers in them.
SLACK, READ = 50000, 25000
LOCKSTEP_OVER = SLACK + 3 * READ


def default_program():
    where = os.environ.get("TCS_PROGRAMS")
    return os.path.join(where, "idioms") if where else os.path.join(ROOT, "build", "tests", "programs", "idioms")


def default_tcs_run():
    return os.environ.get("TCS_RUN") or os.path.join(ROOT, "build", "tools", "tcs-run")


def default_python():
    return os.environ.get("TCS_PYTHON") or sys.executable


class Config:
    def __init__(self, program=None, tcs_run=None, python=None, timeout=TIMEOUT):
        self.program = program or default_program()
        self.tcs_run = tcs_run or default_tcs_run()
        self.python = python or default_python()
        self.timeout = timeout
        self._notices = {}

    def machine_notices(self, mode):
        """The lines tcs-run prints of `true` in that mode here: what it
        says of every program on this machine, not of the case's."""
        if mode not in self._notices:
            r = subprocess.run([self.tcs_run, "-q", "-m", mode, "--", "true"], capture_output=True, text=True,
                               timeout=60, stdin=subprocess.DEVNULL)
            self._notices[mode] = set(r.stderr.splitlines())
        return self._notices[mode]


def end_session(sid):
    """Kills every process of the session: each to normal scheduling and
    free to run on any core first (a process killed on a core where a
    SCHED_FIFO process spins cannot run to die), SIGCONT to one that tcs
    stopped, then SIGKILL; until none is left (a process forked meanwhile
    is caught by the next round)."""
    every_core = set(range(os.cpu_count() or 1))
    for _ in range(250):
        left = [pid for pid, state, _ in session_processes(sid) if state != "Z"]
        if not left:
            return
        for pid in left:
            for act in (lambda p: os.sched_setscheduler(p, os.SCHED_OTHER, os.sched_param(0)),
                        lambda p: os.sched_setaffinity(p, every_core),
                        lambda p: os.kill(p, signal.SIGCONT), lambda p: os.kill(p, signal.SIGKILL)):
                try:
                    act(pid)
                except OSError:
                    pass
        time.sleep(0.02)


PR_SET_PDEATHSIG = 1


def _starter(cpu):
    """What a run's child does before exec: die with this runner (meson's
    timeout kills the runner, not the sessions it started; safe here, the
    runner has one thread), and keep to its core if it has one."""
    def pre():
        ctypes.CDLL(None).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
        if cpu is not None:
            os.sched_setaffinity(0, {cpu})
    return pre


class Run:
    """One case in one mode ('native', 'cpu' or 'lockstep')."""

    def __init__(self, case, mode, cfg):
        self.case, self.mode, self.cfg = case, mode, cfg
        program = [cfg.python, IDIOMS_PY] if case.python else [cfg.program]
        argv = program + case.args()
        self.argv = argv if mode == "native" else [cfg.tcs_run, "-m", mode, "--"] + argv
        self.returncode = None
        self.not_run = False  # the wall budget ran out before it started
        self.timed_out = False
        self.left_behind = []
        self.stdout = self.stderr = ""
        self.wall = 0.0
        self.proc = None

    def start(self, cpu=None):
        """Starts it, on that core alone if given (tcs-run then keeps its
        controllers and itself there)."""
        self.out = tempfile.TemporaryFile()
        self.err = tempfile.TemporaryFile()
        self.t0 = time.monotonic()
        self.proc = subprocess.Popen(self.argv, stdin=subprocess.DEVNULL, stdout=self.out, stderr=self.err,
                                     start_new_session=True, preexec_fn=_starter(cpu))

    def poll(self):
        """True once the run is over (ended, or killed at its timeout)."""
        if self.proc.poll() is None:
            if time.monotonic() - self.t0 <= self.cfg.timeout:
                return False
            self.timed_out = True
            end_session(self.proc.pid)
            self.proc.wait()
        self.wall = time.monotonic() - self.t0
        self.returncode = self.proc.returncode
        self._leftovers()
        for f, name in ((self.out, "stdout"), (self.err, "stderr")):
            f.seek(0)
            setattr(self, name, f.read().decode(errors="replace"))
            f.close()
        return True

    def _leftovers(self):
        """Whatever of the session outlives the run, after a grace for a
        loaded machine to let it exit, is noted and killed."""
        deadline = time.monotonic() + 2.0
        while True:
            left = [p for p in session_processes(self.proc.pid) if p[1] != "Z"]
            if not left or time.monotonic() > deadline:
                break
            time.sleep(0.02)
        if left:
            self.left_behind = left
            end_session(self.proc.pid)

    def values(self):
        return dict(re.findall(r"^([A-Za-z_]\w*)=(\S*)$", self.stdout, re.M))

    def warnings(self):
        """What tcs said of this run beyond its summary and beyond what it
        says of any program on this machine in this mode (the slowclock
        setup's TSC notice, say)."""
        usual = self.cfg.machine_notices(self.mode)
        return [line for line in self.stderr.splitlines()
                if FROM_TCS.search(line) and (not SUMMARY.match(line) or OUTSIDE.search(line)) and line not in usual]


def _stop(sig, frame):
    raise SystemExit(128 + sig)


def execute(runs, jobs, on_done=None, cpus=None, budget=None):
    """Runs them, at most jobs at once, in their order; on_done(run) as
    each ends. cpus: a core per job slot (cpus[i % len]): runs in
    different slots then never share a core, so that one spinning at
    real-time priority cannot starve another. budget: wall seconds after
    which no run starts (those left are not_run), so that a corpus that
    hangs everywhere still ends, with its list, inside a test's timeout.
    If this runner is stopped (SIGTERM, SIGINT), what it started is killed
    first."""
    pending = collections.deque(runs)
    active = {}  # slot -> run
    end = time.monotonic() + budget if budget else None
    old = {s: signal.signal(s, _stop) for s in (signal.SIGTERM, signal.SIGINT)}
    try:
        while pending or active:
            if end and time.monotonic() > end:
                while pending:
                    r = pending.popleft()
                    r.not_run = True
                    if on_done:
                        on_done(r)
            for slot in range(jobs):
                if pending and slot not in active:
                    active[slot] = pending.popleft()
                    active[slot].start(cpus[slot % len(cpus)] if cpus else None)
            time.sleep(0.005)
            for slot, r in list(active.items()):
                if r.poll():
                    del active[slot]
                    if on_done:
                        on_done(r)
    finally:
        for r in active.values():
            if r.proc:  # (None: it failed to start)
                end_session(r.proc.pid)
        for s, h in old.items():
            signal.signal(s, h)


def judge(run, native=None):
    """The run's problems as (kind, reason), the gravest first; [] if it
    passed. native: the native run of its case (for a tcs run)."""
    problems = []
    v = run.values()
    under_tcs = run.mode != "native"
    warned = run.warnings() if under_tcs else []
    rc = run.returncode
    if run.not_run:
        return [("not run", "the wall budget was spent before it started")]
    if run.timed_out:
        problems.append(("hang", "no end after %d s of wall time" % run.cfg.timeout))
    elif rc < 0:
        problems.append(("crash", "killed by %s" % signal.Signals(-rc).name))
    elif under_tcs and rc >= 128:
        problems.append(("crash", "killed by %s" % signal.Signals(rc - 128).name))
    elif rc == 3 and "ok" not in v:
        said = [l for l in run.stderr.splitlines() if l.startswith("idioms:")]
        problems.append(("wrong", "could not set up: %s" % (said[0] if said else "exit 3")))
    elif under_tcs and rc == 2 and "ok" not in v:
        last = run.stderr.strip().splitlines()[-1:] or ["(nothing on stderr)"]
        problems.append(("crash", "tcs-run failed: %s" % last[0]))
    elif "ok" not in v:
        problems.append(("wrong", "no report (exit %d)" % rc))
    elif v.get("ok") != "1" or rc != 0:
        why = v.get("first_failure", "-")
        if why == "-":
            why = "gave up" if v.get("gave_up") == "1" else "stray signals" if v.get("stray_signals", "0") != "0" \
                else "%s of %d calls" % (v.get("calls"), 20)
        if v.get("first_failure_in") == "interrupted":
            why += " (in the interrupted flow)"
        problems.append(("wrong", why))
    if under_tcs and "ok" in v and not problems:
        nv = native.values() if native else {}
        if v.get("device_absent", "0") != "0":
            problems.append(("wrong", "a device was absent under tcs"))
        over = int(v.get("call_sleep_over_max_ns", "-1"))
        if run.mode == "lockstep" and over > LOCKSTEP_OVER:
            problems.append(("wrong", "a wait lasted %d ns more than it asked (lockstep: at most %d)" %
                             (over, LOCKSTEP_OVER)))
        if nv.get("ok") == "1":
            if v.get("calls") != nv.get("calls"):
                problems.append(("wrong", "%s calls, natively %s" % (v.get("calls"), nv.get("calls"))))
            if v.get("timerslack_ns", "-1") != nv.get("timerslack_ns", "-1"):
                problems.append(("wrong", "timer slack %s ns, natively %s ns" %
                                 (v.get("timerslack_ns"), nv.get("timerslack_ns"))))
    if warned:
        problems.append(("warning", warned[0]))
    if run.left_behind:
        problems.append(("leftover", "left %d processes behind (states %s)" %
                         (len(run.left_behind), "".join(s for _, s, _ in run.left_behind))))
    return problems


def describe(run, problems):
    """The FAIL line of a failing run; its other problems follow the first."""
    first = "%s: %s" % problems[0]
    more = "; ".join("%s: %s" % p for p in problems[1:])
    return "FAIL %s %s: %s%s" % (run.mode, run.case.label(), first, " [" + more + "]" if more else "")


def run_cases(cases, modes=MODES, jobs=2, cfg=None, report=None, cpus=None, budget=None, judged=None):
    """Runs every case natively and in each mode; returns [(run, problems)]
    in the cases' order. report(line) is given each FAIL line as it is
    known (a tcs run is judged once its native run has ended), judged(run,
    problems) every run's verdict."""
    cfg = cfg or Config()
    runs, natives, waiting = [], {}, collections.defaultdict(list)
    for c in cases:
        runs.append(Run(c, "native", cfg))
        runs += [Run(c, m, cfg) for m in modes]
    verdicts = {}

    def settle(r):
        verdicts[id(r)] = problems = judge(r, natives.get(r.case))
        if problems and report:
            report(describe(r, problems))
        if judged:
            judged(r, problems)

    def done(r):
        if r.mode == "native":
            natives[r.case] = r
            settle(r)
            for w in waiting.pop(r.case, []):
                settle(w)
        elif r.case in natives:
            settle(r)
        else:
            waiting[r.case].append(r)

    execute(runs, jobs, done, cpus, budget)
    return [(r, verdicts[id(r)]) for r in runs]


def check_program(cfg):
    """The program's calls are cases.py's (None), or what differs."""
    out = subprocess.run([cfg.program, "--list"], capture_output=True, text=True, timeout=10)
    listed = collections.OrderedDict((l.split()[0], set(l.split()[1:])) for l in out.stdout.splitlines() if l.strip())
    if listed != corpus.CALLS:
        a, b = set(listed), set(corpus.CALLS)
        return "idioms --list and cases.py differ: only in the program %s, only in cases.py %s, or their flags" % (
            sorted(a - b), sorted(b - a))
    return None


class Recorded:
    """A run as a --results file keeps it."""

    def __init__(self, d):
        self.mode, self.case = d["mode"], corpus.Case(*d["case"])
        self.returncode, self.wall, self.stderr, self._values = d["returncode"], d["wall"], d["stderr"], d["values"]

    def values(self):
        return self._values


def resume(path, cases, modes):
    """What a --results file has of these cases, as [(run, problems)], and
    the cases it lacks any run of (run again whole: a tcs run is judged
    against its native run)."""
    have = {}
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                try:
                    d = json.loads(line)
                except ValueError:
                    continue  # a line cut short when the run was killed
                have[(d["mode"], tuple(d["case"]))] = (Recorded(d), [tuple(p) for p in d["problems"]])
    kept, todo = [], []
    for c in cases:
        if all((m, tuple(c)) in have for m in modes):
            kept += [have[(m, tuple(c))] for m in modes]
        else:
            todo.append(c)
    return kept, todo


def tally(results):
    """(passed, failed, Counter of the first problem's kind per failure)."""
    kinds = collections.Counter(p[0][0] for _, p in results if p)
    failed = sum(kinds.values())
    return len(results) - failed, failed, kinds


def main(argv=None):
    ap = argparse.ArgumentParser(description="Runs the idiom corpus natively and under tcs-run.")
    ap.add_argument("--seed", type=int, default=corpus.SEED, help="the sample's seed (default %(default)s)")
    ap.add_argument("--count", type=int, default=corpus.COUNT, help="the sample's size (default %(default)s)")
    ap.add_argument("--all", action="store_true", help="the whole product instead of a sample")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once (default %(default)s)")
    ap.add_argument("--mode", choices=("cpu", "lockstep", "both", "native"), default="both",
                    help="the tcs mode(s) to run besides the native run (native: that alone)")
    ap.add_argument("--filter", help="only cases whose label ('context call interrupted') this regex finds")
    ap.add_argument("--cpus", help="a core per job, e.g. 0,1 (default: wherever tcs-run puts them)")
    ap.add_argument("--budget", type=float, help="wall seconds after which no run starts (default: none)")
    ap.add_argument("--timeout", type=float, default=TIMEOUT, help="wall seconds per run (default %(default)s)")
    ap.add_argument("--program", help="the idioms binary")
    ap.add_argument("--tcs-run", help="tcs-run")
    ap.add_argument("--python", help="the Python for idioms.py")
    ap.add_argument("--list", action="store_true", help="print the cases and stop")
    ap.add_argument("--results", help="a file of every run's result, a JSON line each, written as each is "
                    "judged; cases it already has whole are not run again (a long run resumes)")
    a = ap.parse_args(argv)
    cases = corpus.all_cases() if a.all else corpus.sample(a.seed, a.count)
    if a.filter:
        cases = [c for c in cases if re.search(a.filter, c.label())]
    if a.list:
        for c in cases:
            print(c.label())
        return 0
    cfg = Config(a.program, a.tcs_run, a.python, a.timeout)
    wrong = check_program(cfg)
    if wrong:
        print(wrong, file=sys.stderr)
        return 1
    modes = MODES if a.mode == "both" else () if a.mode == "native" else (a.mode,)
    t0 = time.monotonic()
    cpus = [int(c) for c in a.cpus.split(",")] if a.cpus else None
    kept, todo = resume(a.results, cases, ("native",) + tuple(modes)) if a.results else ([], cases)
    for r, p in kept:
        if p:
            print(describe(r, p))
    out = open(a.results, "a") if a.results else None

    def keep(r, p):
        out.write(json.dumps({"mode": r.mode, "case": list(r.case), "problems": p, "returncode": r.returncode,
                              "wall": round(r.wall, 3), "values": r.values(), "stderr": r.stderr[-2000:]}) + "\n")
        out.flush()

    results = kept + run_cases(todo, modes, a.jobs, cfg, report=lambda line: print(line, flush=True), cpus=cpus,
                               budget=a.budget, judged=keep if out else None)
    passed, failed, kinds = tally(results)
    print("# %d cases x (%s) in %.1f s wall%s" % (
        len(cases), " + ".join(("native",) + tuple(modes)), time.monotonic() - t0,
        "; failures: " + ", ".join("%s %d" % kv for kv in sorted(kinds.items())) if failed else ""))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
