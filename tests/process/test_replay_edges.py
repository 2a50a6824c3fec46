"""--record and --replay at their edges (docs/DESIGN.md §2, Record and
replay; §9; tcs-run(1), LIMITATIONS):
- what a program does after the run's end began (here: after --duration's
  SIGTERM) is no departure from the record, while a change before the end
  is one, said once;
- what a program writes on a wire is not in the record, so a replay that
  writes more is reported at the next request, whose time differs;
- a program that reads its clocks more often between two stops than its
  journal holds (174,752 entries) is warned of once when recorded, the
  warning saying that a replay departs there, and its replay does."""

import os
import re
import tempfile

from harness import AHEAD, check, main, prog, scenario_file, tcs

MS = 1000000
# --epoch's CLOCK_MONOTONIC origin (docs/DESIGN.md §2, Clocks).
EPOCH_MONOTONIC = 100000 * 10**9


def tmp(name):
    return os.path.join(tempfile.gettempdir(), "tcs-test-replay-edges-%d-%s" % (os.getpid(), name))


def departures(r):
    return [line for line in r.stderr.splitlines() if "departs" in line]


def test_what_follows_the_end_is_no_departure():
    path = tmp("end.mcap")
    try:
        r = tcs("-q", "-d", "20ms", "--record", path, "--", prog("after_end"), "1", "1", timeout=60)
        check(r.returncode == 0 and r.values().get("after") == "1", "recorded: a 1 ms loop ended by -d 20ms", r)
        # After SIGTERM, five sleeps and clock reads where the record has one.
        p = tcs("-q", "--replay", path, "--", prog("after_end"), "1", "5", timeout=60)
        check(p.returncode == 0 and p.values().get("after") == "5", "the replay runs to its end", p)
        check(departures(p) == [], "what it did after the end's SIGTERM is no departure", p)
        check(p.values().get("loops") == r.values().get("loops"), "and until then it kept to the record", p)
        # Before the end, another period departs: said once.
        p = tcs("-q", "--replay", path, "--", prog("after_end"), "2", "1", timeout=60)
        check(p.returncode == 0 and len(departures(p)) == 1, "a 2 ms loop departs from the 1 ms record, said once", p)
    finally:
        if os.path.exists(path):
            os.unlink(path)


SERIAL = """\
[[model]]
name = "pendulum"
type = "pendulum"
[[serial]]
path = "/dev/ttyUSB0"
baud = 57600
"""
BAUD = 57600


def byte_times(n):
    """n bytes sent back to back on an 8N1 line: 10 bits each (§9), in ns."""
    return n * 10 * 10**9 // BAUD


def test_a_wire_departure_is_reported_at_the_next_request():
    path = tmp("wire.mcap")
    try:
        with scenario_file(SERIAL) as world:
            r = tcs("-q", "-w", world, "--epoch", "0", "--record", path, "--", prog("wire_drain"), "/dev/ttyUSB0", "10",
                    timeout=60)
            check(r.returncode == 0, "recorded: 10 bytes written and drained, three times", r)
            p = tcs("-q", "-w", world, "--replay", path, "--", prog("wire_drain"), "/dev/ttyUSB0", "20", timeout=60)
        check(p.returncode == 0, "a replay writing 20 bytes instead runs to its end", p)
        said = departures(p)
        check(len(said) == 1 and "goes on live" in said[0], "it departs, said once, and goes on live", p)
        # The first write is where the record's clocks still hold (its time
        # is the record's); its 20 bytes leave 20 byte times later (10 more
        # than the record's), the drain's end: the next request after the
        # write, where the departure shows. Not later than the 1 ms sleep
        # after it, the request after that; not before the drain's end, but
        # for what a clock read runs ahead in cpu mode (AHEAD).
        write_at = int(r.values()["write_at"]) - EPOCH_MONOTONIC
        at = int(round(float(re.search(r"departs from the record at ([0-9.]+) s", said[0]).group(1)) * 1e9))
        lo, hi = write_at + byte_times(20) - AHEAD, write_at + byte_times(20) + MS
        print("  written at %d ns; departure reported at %d ns (%d to %d)" % (write_at, at, lo, hi))
        check(lo <= at <= hi, "the departure is at the drain's end (%d ns), by the next request: %d ns" %
              (write_at + byte_times(20), at), p)
        # And said then: the coordinator says it as it takes that request
        # (the sleep's), before its answer, so before the program's line
        # after the sleep (both write to this one pipe, stderr).
        lines = p.stderr.splitlines()
        check(lines.index(said[0]) < lines.index("wire_drain: slept 0"),
              "the departure is said at that request, before the first sleep returns", p)
    finally:
        if os.path.exists(path):
            os.unlink(path)


def test_a_journal_overflow_is_warned_of_and_departs():
    path = tmp("overflow.mcap")
    # CPU scale 0.001: a 1 ms step is 1 s of this machine's CPU, so no stop
    # falls among the reads (a million reads take tens of ms).
    try:
        for reads, overflows in ((100000, False), (1000000, True)):
            r = tcs("-q", "--cpu-scale", "0.001", "--record", path, "--", prog("clock_reads"), str(reads), timeout=120)
            check(r.returncode == 0 and r.values().get("backwards") == "0", "%d reads recorded" % reads, r)
            warned = [line for line in r.stderr.splitlines() if "warning: record:" in line]
            p = tcs("-q", "--replay", path, timeout=120)
            check(p.returncode == 0 and p.stdout == r.stdout, "%d reads: the replay runs to its end" % reads, p)
            if not overflows:
                check(warned == [] and departures(p) == [],
                      "%d reads fit the journal: no warning, and the replay keeps to the record" % reads, (r, p))
                continue
            said = "'%s' read its clocks more often between two stops than its journal holds; " \
                   "the record is incomplete from" % prog("clock_reads")
            check(len(warned) == 1 and said in warned[0] and "where a replay departs" in warned[0],
                  "%d reads between two stops: warned once that the record is incomplete" % reads, r)
            check(len(departures(p)) == 1, "and its replay departs, said once", p)
    finally:
        if os.path.exists(path):
            os.unlink(path)


if __name__ == "__main__":
    main(globals())
