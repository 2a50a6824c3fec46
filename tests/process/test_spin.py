"""Spins in lockstep (docs/DESIGN.md §2): a loop that waits by reading the
clock, or by reading or polling a device that has nothing yet, makes no
wait, and in lockstep only waits move virtual time; so each such call made
without a wait since the last one costs what it costs natively, and the
spin ends where it would on the machine instead of hanging. With --epoch
the costs are fixed (25 ns a clock read, 500 ns an empty read) so that a
run repeats; --spin-cost sets them. Checked with tests/programs/spin.c."""

import json
import os
import tempfile

from harness import AHEAD, READ, SLACK, TCS_TRACE, check, main, prog, run, scenario_file, tcs, trace_rows
from test_devices import SCENARIO as STREAM  # (a 1 kHz stream sensor, /dev/tcs/pendulum/state)

MS = 1000000
EPOCH_MONO = 100000 * 1000 * MS  # CLOCK_MONOTONIC at virtual 0 with --epoch


def spin(*args, options=(), mode="lockstep"):
    r = tcs("-q", "-m", mode, *options, prog("spin"), *args, timeout=60)
    check(r.returncode == 0, "spin %s ends" % " ".join(args), r)
    return {k: int(v) for k, v in r.values().items()}, r


def test_a_clock_spin_ends_at_its_deadlines():
    # 100 deadlines 1 ms apart, each waited for by reading the clock.
    # With the nominal 25 ns a read, each deadline is met exactly by a read.
    v, r = spin("clock", "100", str(MS), options=("--epoch", "0"))
    check(v["span"] == 100 * MS and v["late"] == 0, "--epoch: 100 x 1 ms of spinning end at exactly 100 ms", r)
    check(v["reads"] == 100 * MS // 25 + 1, "one read every 25 ns of virtual time, and the first free", r)
    # The summary tells spins from waits: the program made none of its own,
    # and its spin stopped at each of the world's 100 steps.
    with tempfile.TemporaryDirectory(prefix="tcs-test-spin-") as d:
        path = os.path.join(d, "run.mcap")
        r = tcs("-m", "lockstep", "--epoch", "0", "-t", path, prog("spin"), "clock", "100", str(MS), timeout=60)
        check("exited 0; 0 waits; 100 spin stops (lockstep: see --spin-cost)" in r.stderr,
              "the summary: no waits, 100 spin stops", r)
        spins = [w for w in trace_rows(path, "/tcs/wait") if w["kind"] == "spin"]
        check(len(spins) == 100 and all(int(w["v_end_ns"]) % MS == 0 for w in spins),
              "the trace has them as waits of kind spin, each at a step", r)
        s = run([TCS_TRACE, "summary", "--json", path])
        check(json.loads(s.stdout)["controllers"][0]["cycles"] == 0, "tcs-trace summary counts no cycles", s)
    # Measured costs (this machine's, once at start-up): every read after
    # the first costs the same whole number of ns, so the reads fall on a
    # grid from the first, the span a whole number of steps of it; each
    # deadline is met by the first read on or past it, which fixes the
    # span and the lateness exactly.
    v, r = spin("clock", "100", str(MS))
    cost, rest = divmod(v["span"], v["reads"] - 1)
    check(rest == 0 and 1 <= cost <= READ,
          "measured costs: %d reads in %d ns, each a clock read's cost (at most READ)" % (v["reads"], v["span"]), r)
    met = [-(-i * MS // cost) * cost for i in range(1, 101)]
    late = max(m - i * MS for i, m in zip(range(1, 101), met))
    check(v["span"] == met[-1] and v["late"] == late,
          "measured costs: every deadline met by the first read past it, %d ns a read: span %d (%d), late %d (%d)" %
          (cost, v["span"], met[-1], v["late"], late), r)


def test_spin_costs_are_set_by_the_user():
    v, r = spin("clock", "10", str(MS), options=("--spin-cost", "1us,2us"))
    check(v["span"] == 10 * MS and v["reads"] == 10 * 1000 + 1, "--spin-cost 1us: a read each microsecond", r)
    r = tcs("-q", "-m", "lockstep", "--spin-cost", "2ms", prog("spin"), "clock", "1", "1")
    check(r.returncode == 2 and "--spin-cost: '2ms': at most 1.000 ms each" in r.stderr,
          "a cost over 1 ms is refused, naming the option", r)


def test_an_empty_device_is_read_until_its_record():
    with scenario_file(STREAM) as world:
        # Nominal: 500 ns an empty read or poll; records every whole ms.
        v, r = spin("device", "/dev/tcs/pendulum/state", options=("--epoch", "0", "-w", world))
        check(v["at"] - EPOCH_MONO == MS and v["tries"] == 2000,
              "reads at 500 ns each find the next record when it is due, at 1 ms", r)
        check(v["poll_at"] - EPOCH_MONO - 2 * MS == 25 and v["poll_tries"] == 1999,
              "zero-timeout polls find it at 2 ms (and the clock read after costs 25 ns)", r)
        # Measured costs: within a few microseconds of when it is due.
        v, r = spin("device", "/dev/tcs/pendulum/state", options=("--epoch", "0", "--spin-cost", "24ns,1us",
                                                                 "-w", world))
        check(v["at"] - EPOCH_MONO == MS and v["tries"] == 1000, "--spin-cost 1us: 1000 reads to the record", r)
        v, r = spin("device", "/dev/tcs/pendulum/state", options=("-w", world))
        check(v["tries"] > 0 and v["poll_tries"] > 0, "measured costs: reads and polls found nothing first", r)


def test_a_spin_meets_timers_and_other_threads():
    # A signal timer's handler runs at its expiry (timers have no slack).
    v, r = spin("alarm", "10", options=("--epoch", "0"))
    check(v["alarm_ns"] == 10 * MS, "a spin for a 10 ms itimer's flag sees it at 10 ms", r)
    # Another thread's sleep ends at its deadline and slack; it runs then.
    v, r = spin("thread", "5", options=("--epoch", "0"))
    check(v["thread_ns"] == 5 * MS + SLACK, "a spin for a thread's 5 ms sleep sees its flag at 5.05 ms", r)
    # Measured costs: the first read on or past 5.05 ms sees it, a read's
    # cost late at most (a clock read's, at most READ).
    v, r = spin("thread", "5")
    check(5 * MS + SLACK <= v["thread_ns"] < 5 * MS + SLACK + READ,
          "measured costs: at 5.05 ms, within a read's cost", r)


def test_two_runs_with_an_epoch_repeat():
    runs = [spin("thread", "3", options=("--epoch", "0"))[1].stdout for _ in range(2)]
    runs += [spin("clock", "20", str(MS // 3), options=("--epoch", "0"))[1].stdout for _ in range(2)]
    check(runs[0] == runs[1] and runs[2] == runs[3], "the same output twice: %r" % runs)


def test_cpu_mode_charges_the_spin_itself():
    # There the spin's CPU moves virtual time: it ends too. The deadlines
    # are t0 + i ms, so late only at the last: by the read that found it
    # past (one read's cost, READ) and how far the read's estimate of the
    # CPU may be off (AHEAD). A lone controller is never preempted (it is
    # nobody's turn but its own), so no stop's cost comes in between.
    v, r = spin("clock", "20", str(MS), mode="cpu")
    check(20 * MS <= v["span"] <= 20 * MS + READ + AHEAD,
          "cpu mode: 20 x 1 ms of spinning take 20 ms, but for the last read: %d ns" % v["span"], r)
    check(0 <= v["late"] <= READ + AHEAD, "cpu mode: no deadline seen later than a read: %d ns" % v["late"], r)


if __name__ == "__main__":
    main(globals())
