"""The Dynamixel example (examples/dynamixel): balance.py, a Python
controller of our own that balances the built-in pendulum through an
XM430-W350 on a 1 Mbit/s serial line. It balances in both modes; and the
TCS paper's verdict through it: with a control law its loop cannot afford,
the pendulum falls in cpu mode, as it would on the robot, while lockstep
reports success for the same program and the same work. Whether it stayed
up or fell is read from the run's trace (the world's own state,
world_trace.py), not from the controller's verdict."""

import os
import tempfile

from harness import PYTHON, check, main, run_balancer
from world_trace import pendulum_off_upright

EXAMPLE = os.path.join(os.environ.get("TCS_EXAMPLES_SRC", "examples"), "dynamixel")
SCENARIO = os.path.join(EXAMPLE, "pendulum.toml")
CONTROLLER = os.path.join(EXAMPLE, "balance.py")
MS = 1000000
# A cycle's bus time at 1 Mbit/s (10 bits a byte): a READ of 8 bytes (14
# out, 19 back) and a WRITE of Goal Current (14 out, 11 back), each
# answered after the factory Return Delay Time, 500 us.
BUS_NS = (14 + 19 + 14 + 11) * 10 * 1000 + 2 * 500000


def run(mode, *args, options=()):
    """balance.py under tcs-run, with a trace: its key=value pairs, the
    result, and the rod's largest distance from upright in the world over
    the run's last 2 s (the controller's window)."""
    with tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "run.mcap")
        v, r = run_balancer(mode, SCENARIO, [PYTHON, CONTROLLER], args, tuple(options) + ("-t", trace), timeout=240)
        off, _ = pendulum_off_upright(trace, 2)
    return v, r, off


def test_it_balances_in_both_modes():
    for mode in ("lockstep", "cpu"):
        v, r, off = run(mode)
        check(off < 0.1, "%s: the world's rod within 0.1 rad of upright over the last 2 s (%.4f)" % (mode, off), r)
        check(v["balanced"] == "1", "%s: and the controller says so" % mode, r)
        # 100 Hz for 5 s on a fixed schedule (a late cycle is caught up),
        # the bus's 1.58 ms and the law's computing well within each 10 ms.
        check(v["cycles"] == "500" or (mode == "cpu" and v["cycles"] == "499"),
              "%s: at its rate, %s cycles in 5 s" % (mode, v["cycles"]), r)
        if mode == "lockstep":
            # Computation is free, the wire is not: the bus's time a cycle
            # is its bytes' and return delays', exactly. A transaction's
            # first clock read may cost a spin's read (docs/DESIGN.md §2),
            # but before its write; its last follows a read that got the
            # reply's bytes, and costs nothing. (bus_ms: 0.1 µs digits.)
            check(v["misses"] == "0" and v["bus_ms"] == "%.4f" % (BUS_NS / MS),
                  "lockstep: no miss, %s ms of bus a cycle (%.4f ms of bytes and delays)" %
                  (v["bus_ms"], BUS_NS / MS), r)


def test_an_overloaded_loop_falls_in_cpu_mode_but_lockstep_says_fine():
    # 200 ms of the program's CPU a cycle (--work-ms counts its CPU clock,
    # so this is the same work on any machine) in a 10 ms period: the loop
    # falls to about 5 Hz, and a PD law acting 200 ms late lets the rod
    # lean past where the servo's 4.1 N*m can hold its 4.9: it falls. The
    # margins, measured here: with 40 ms a cycle it still balances (24 Hz),
    # with 80 ms it swings 0.27 rad either side, from about 120 ms it falls.
    # The work is the same on any machine; the interpreter's own computing
    # (a few tenths of a millisecond a cycle here, some ms on a slow
    # machine) is far from either edge, and only adds to the overload. The
    # plain run has as much margin the other way: 1.8 ms of bus and
    # interpreter a cycle where 40 ms still balance.
    v, r, off = run("cpu", "--work-ms", "200", "--seconds", "3")
    check(off > 1.0, "cpu: it falls, the world's rod more than 1 rad from upright in the last 2 s (%.3f)" % off, r)
    check(v["balanced"] == "0", "cpu: and the controller says so", r)
    check(v["misses"] == v["cycles"] and int(v["cycles"]) <= 3000 // 200 + 1,
          "cpu: every deadline missed, a cycle every 200 ms at most (%s cycles)" % v["cycles"], r)
    # Lockstep: the same program and work. It is free there, so --cpu-scale
    # (which only makes the program's CPU clock run faster in lockstep)
    # lets the 200 ms its clock counts burn a tenth of this machine's time.
    v, r, off = run("lockstep", "--work-ms", "200", "--seconds", "3", options=("--cpu-scale", "10"))
    check(v["balanced"] == "1" and (v["cycles"], v["misses"]) == ("300", "0"),
          "lockstep: 300 cycles at 100 Hz, no miss, balanced: success reported", r)
    check(off < 0.1, "lockstep: and the simulated rod did stay up (%.4f rad off at most)" % off, r)


if __name__ == "__main__":
    main(globals())
