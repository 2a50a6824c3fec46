"""--record and --replay (docs/DESIGN.md §2): a cpu-mode run recorded with
--record repeats under --replay with every CPU charge and clock value taken
from the record: the same output, the same commands at the same virtual
times, the same world and the same verdict, where two live runs of the same
overloaded controller differ. A controller changed since is reported at its
first departure, once, and the run goes on live. Records that cannot be
replayed are refused with exit 2."""

import os
import re
import tempfile

from harness import PYTHON, TCS_TRACE, check, main, run, tcs, trace_rows

EXAMPLES = os.environ.get("TCS_EXAMPLES", "examples")
PD = os.path.join(EXAMPLES, "pendulum_pd")
PD_CPP = os.path.join(EXAMPLES, "pendulum_pd_cpp")
# The paper's overloaded loop: 300 us of this machine's CPU a cycle on a
# target six times slower, at 1 kHz: it misses every deadline and falls.
OVERLOADED = ["--seconds", "2", "--work-us", "300"]
SCALE = "6"

# A Python program whose output is all clocks, CPU time and randomness.
SCRIPT = """\
import os, random, time
t0 = time.monotonic()
x = 0
for i in range(100):
    for k in range(2000):
        x += k * k
    time.sleep(0.001)
    if i % 25 == 0:
        print("i=%d t=%.9f cpu=%.9f r=%r" % (i, time.monotonic() - t0, time.process_time(), random.random()))
print("end t=%.9f urandom=%s" % (time.monotonic() - t0, os.urandom(4).hex()))
"""


def tmp(name):
    return os.path.join(tempfile.gettempdir(), "tcs-test-replay-%d-%s" % (os.getpid(), name))


def record(path, argv, *options):
    r = tcs("--record", path, *options, "--", *argv, timeout=120)
    check(r.returncode == 0, "a recorded run of %s" % argv[0], r)
    check("warning: record:" not in r.stderr, "recorded whole (no clock read lost)", r)
    return r


def replay(path, argv, *options):
    return tcs("--replay", path, *options, "--", *argv, timeout=120)


def commands(path):
    """Every command: its virtual time, device and values; each
    controller's in its order (two controllers' are logged as the
    coordinator takes them, in whichever order they ran on their cores)."""
    rows = trace_rows(path, "/tcs/device")
    return sorted(rows, key=lambda row: int(row["controller"]))


def joints(path):
    """The world at every step (less the wall time it took)."""
    return [{k: v for k, v in row.items() if not k.startswith("wall")} for row in trace_rows(path, "/tcs/step")]


def summary(path):
    """tcs-trace summary, less what the machine decides (wall times, pids,
    tcs's own overhead)."""
    r = run([TCS_TRACE, "summary", path])
    check(r.returncode == 0, "tcs-trace summary %s" % path, r)
    return [re.sub(r" \(pid \d+\)", "", line) for line in r.stdout.splitlines()
            if "wall" not in line and "timing error" not in line]


def test_an_overloaded_pendulum_replays_exactly():
    a, b, again = tmp("a.mcap"), tmp("b.mcap"), tmp("again.mcap")
    try:
        ra = record(a, [PD] + OVERLOADED, "--cpu-scale", SCALE)
        rb = record(b, [PD] + OVERLOADED, "--cpu-scale", SCALE)
        check(ra.values()["balanced"] == "0", "overloaded, the pendulum falls", ra)
        # Two live runs: this machine's CPU decides each charge, so their
        # commands come at other times (to the nanosecond), and mostly their
        # output differs too.
        check(commands(a) != commands(b), "two live runs differ in their commands' times")
        p = replay(a, [PD] + OVERLOADED, "-t", again)
        check(p.returncode == 0 and "departs" not in p.stderr, "the replay keeps to the record", p)
        check(p.stdout == ra.stdout, "the replay prints what the recorded run printed, byte for byte", p)
        check(commands(again) == commands(a), "the same commands at the same virtual times")
        check(joints(again) == joints(a), "the same world, step by step")
        check(summary(again) == summary(a), "tcs-trace summary of the record and of its replay agree (verdict too)",
              (summary(a), summary(again)))
        alone = tcs("--replay", a, timeout=120)
        check(alone.stdout == ra.stdout, "--replay without a PROGRAM runs the recorded one, as it was run", alone)
        size = os.path.getsize(a)
        cycles = int(ra.values()["cycles"])
        print("  %d cycles recorded in %d bytes (%.1f KiB per 1000 cycles); live runs %s and %s cycles" % (
            cycles, size, size / 1024 / cycles * 1000, ra.values()["cycles"], rb.values()["cycles"]))
    finally:
        for f in (a, b, again):
            if os.path.exists(f):
                os.unlink(f)


def test_cpp_and_python_controllers_replay():
    path = tmp("prog.mcap")
    try:
        for name, argv, options in (("C++", [PD_CPP] + OVERLOADED, ("--cpu-scale", SCALE)),
                                    ("Python", [PYTHON, "-c", SCRIPT], ())):
            r = record(path, argv, *options)
            p = replay(path, argv)
            check(p.returncode == 0 and "departs" not in p.stderr and p.stdout == r.stdout,
                  "%s: the replay prints the same bytes, CPU times, clocks and random values included" % name, p)
    finally:
        if os.path.exists(path):
            os.unlink(path)


def test_a_scenarios_controllers_replay_each_at_its_own_scale():
    # Two pendulums, each its own controller; the slower at the scenario's
    # CPU scale 2, the other at tcs-run's 1: each replays its own journal at
    # its own scale (the record's /tcs/controller), without --cpu-scale.
    world = os.path.join(os.environ.get("TCS_SCENARIOS", "."), "two_pendulums.toml")
    env = dict(os.environ, PATH=EXAMPLES + os.pathsep + os.environ.get("PATH", ""))
    path, again = tmp("two.mcap"), tmp("two-again.mcap")
    try:
        r = tcs("-w", world, "-d", "1s", "--record", path, timeout=120, env=env)
        check(r.returncode == 0 and "warning: record:" not in r.stderr, "two controllers recorded", r)
        # (No -d: a replay lasts as long as the recorded run.)
        p = tcs("-w", world, "--replay", path, "-t", again, timeout=120, env=env)
        check(p.returncode == 0 and "departs" not in p.stderr, "their replay keeps to the record", p)
        check(sorted(p.stdout.splitlines()) == sorted(r.stdout.splitlines()) and len(r.stdout.splitlines()) == 4,
              "both print what they printed (in the order they ended)", p)
        check(commands(again) == commands(path), "the same commands, both controllers'")
        check(summary(again) == summary(path), "tcs-trace summary agrees, each controller's CPU scale too",
              (summary(path), summary(again)))
        check([line for line in summary(again) if line.startswith("controller ")] ==
              ["controller 1: pendulum_pd", "controller 2: pendulum_pd, CPU scale 2"],
              "each at its own scale, the slower at 2 (scale 1 goes unsaid)", summary(again))
    finally:
        for f in (path, again):
            if os.path.exists(f):
                os.unlink(f)


def test_a_changed_controller_is_reported_at_its_first_departure():
    path = tmp("changed.mcap")
    try:
        record(path, [PD] + OVERLOADED, "--cpu-scale", SCALE)
        first = [row for row in trace_rows(path, "/tcs/device")][0]
        # Another torque limit: the same requests, another first command.
        p = replay(path, [PD] + OVERLOADED + ["--limit", "4"])
        check(p.returncode == 0, "a departed replay still runs to its end", p)
        said = [line for line in p.stderr.splitlines() if "departs" in line]
        check(len(said) == 1, "the departure is said once", p)
        check("departs from the record at %.9f s: command '4' to /dev/tcs/pendulum/torque where the record has '%s'"
              % (int(first["v_ns"]) / 1e9, first["values[0]"]) in said[0] and "goes on live" in said[0],
              "at the first command's virtual time, with both commands", p)
        # Another rate: its first wait ends elsewhere, and the next request
        # comes where the record has none. A period well beyond a cycle's
        # computing (1.8 ms nominal: at 500 Hz a slow record's cycles, 2.06
        # ms, missed every deadline too, and the replay never departed).
        p = replay(path, [PD, "--rate", "100"] + OVERLOADED)
        said = [line for line in p.stderr.splitlines() if "departs" in line]
        check(p.returncode == 0 and len(said) == 1, "another rate departs, said once", p)
    finally:
        if os.path.exists(path):
            os.unlink(path)


def test_records_that_cannot_be_replayed_are_refused():
    plain, rec = tmp("plain.mcap"), tmp("rec.mcap")
    try:
        r = tcs("-t", plain, "-d", "10ms", "--", "true")
        check(r.returncode == 0, "a plain trace", r)
        record(rec, ["true"])
        with open(tmp("junk.mcap"), "w") as f:
            f.write("not a record\n")
        cases = [
            (["--replay", tmp("none.mcap"), "--", "true"], "No such file or directory"),
            (["--replay", tmp("junk.mcap"), "--", "true"], "not an MCAP file"),
            (["--replay", plain, "--", "true"], "not a record (a trace written without --record)"),
            (["--replay", rec, "--cpu-scale", "2", "--", "true"], "--cpu-scale 2 differs from the record's 1"),
            (["--replay", rec, "-m", "lockstep", "--", "true"], "--replay repeats a cpu-mode run"),
            (["--replay", rec, "-w", os.path.join(os.environ.get("TCS_SCENARIOS", "."), "two_pendulums.toml"),
              "--", "true"], "recorded in another world"),
            (["--record", rec, "-m", "lockstep", "--", "true"], "--record records a cpu-mode run"),
            (["--record", rec, "--replay", rec, "--", "true"], "do not go together"),
            (["--record", rec, "-t", plain, "--", "true"], "no --trace beside it"),
        ]
        for args, said in cases:
            r = tcs(*args)
            check(r.returncode == 2 and said in r.stderr and len(r.stderr.splitlines()) <= 2,
                  "%s: exit 2, saying '%s'" % (" ".join(args), said), r)
    finally:
        for f in (plain, rec, tmp("junk.mcap")):
            if os.path.exists(f):
                os.unlink(f)


if __name__ == "__main__":
    main(globals())
