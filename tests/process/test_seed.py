"""--seed (docs/DESIGN.md §2): the randomness programs draw from the system
(getrandom, getentropy, /dev/urandom, /dev/random) is a stream fixed by N,
one per process (a child's its own), so that with --epoch a lockstep run of
a deterministic program repeats byte for byte: C, C++ and Python programs
that print their clocks and random values (tests/programs/entropy.c,
entropy_cxx.cpp, and a Python script below). Different seeds differ;
without --seed the randomness is the system's."""

from harness import PYTHON, check, main, prog, tcs

SCRIPT = """\
import os, random, time, uuid
time.sleep(0.01)
print("monotonic=%.9f time=%.9f" % (time.monotonic(), time.time()))
print("urandom=" + os.urandom(8).hex())
print("random=%r" % random.random())
print("uuid=%s" % uuid.uuid4())
print("set=" + ",".join({"alpha", "beta", "gamma", "delta", "epsilon", "zeta"}))
"""

PROGRAMS = {"C": [prog("entropy")], "C++": [prog("entropy_cxx")], "Python": [PYTHON, "-c", SCRIPT]}
CLOCKS = ("monotonic", "realtime", "gettimeofday", "steady_ns", "system_ns")


def run(argv, *options):
    r = tcs("-q", "-m", "lockstep", "--epoch", "0", *options, "--", *argv, timeout=60)
    check(r.returncode == 0 and r.stdout, "%s runs" % argv[0], r)
    return r


def randoms(r):
    """The lines that are not clocks."""
    return [line for line in r.stdout.splitlines() if not line.startswith(CLOCKS)]


def test_a_seeded_run_repeats_byte_for_byte():
    for name, argv in PROGRAMS.items():
        a, b = run(argv, "--seed", "42"), run(argv, "--seed", "42")
        check(a.stdout == b.stdout, "%s: two runs with --epoch and --seed 42 print the same bytes" % name, b)
        other = run(argv, "--seed", "43")
        check(all(x != y for x, y in zip(randoms(a), randoms(other))),
              "%s: --seed 43 gives other random values, every one" % name, other)
        check([x for x in a.stdout.splitlines() if x not in randoms(a)] ==
              [x for x in other.stdout.splitlines() if x not in randoms(other)],
              "%s: and the same clocks" % name, other)
        # (A set of six may come out in the same order by chance, 1 in 720:
        # not compared here.)
        real = [[x for x in randoms(run(argv)) if not x.startswith("set=")] for _ in range(2)]
        check(all(x != y for x, y in zip(*real)), "%s: without --seed, the system's randomness (two runs differ)" %
              name, real)
        print("  %-6s %d random values repeat with --seed 42; other with 43 and without" % (name, len(randoms(a))))


def test_every_source_draws_on_from_the_stream():
    # One stream per process: each call takes the next bytes, so no two
    # sources repeat each other; a forked child has a stream of its own.
    v = run(PROGRAMS["C"], "--seed", "7").values()
    values = [v[k] for k in ("getrandom", "getentropy", "syscall_getrandom", "urandom", "random", "fread_urandom")]
    check(len(set(values)) == len(values) and all(x != "0" * 32 for x in values),
          "getrandom, getentropy, syscall, /dev/urandom, /dev/random and fread: each its own bytes: %s" % values)
    check(v["child_getrandom"] != v["parent_getrandom"], "a forked child draws a stream of its own")


def test_bad_seeds_are_refused():
    for bad in ("-1", "x", "18446744073709551616", ""):
        r = tcs("-q", "--seed", bad, "--", "true")
        check(r.returncode == 2 and ("--seed: '%s' is not a whole number" % bad) in r.stderr,
              "--seed %r: exit 2, naming the option" % bad, r)


if __name__ == "__main__":
    main(globals())
