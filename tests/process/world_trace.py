"""The world as a run's trace holds it (/tcs/step: every step's joint
positions and velocities, the simulation's own state, exported by tcs-trace),
so that an example is judged by what its robot did, not by the verdict its
controller prints from what tcs's sensors told it."""

import math

from harness import check, trace_rows


def wrap(angle):
    """An angle in [-pi, pi]."""
    return math.remainder(angle, 2 * math.pi)


def joint_steps(trace, *signals):
    """Each step of the trace as (v_ns, [the signals' values]), the signals
    named as the scenario names them ('pendulum.hinge.position')."""
    rows = trace_rows(trace, "/tcs/step")
    check(rows and all("joint." + s in rows[0] for s in signals),
          "the trace's /tcs/step has %s" % ", ".join(signals), rows[:1])
    return [(int(r["v_ns"]), [float(r["joint." + s]) for s in signals]) for r in rows]


def last(steps, seconds):
    """The steps of the last `seconds` before the trace's last one."""
    end = steps[-1][0]
    return [s for s in steps if s[0] > end - seconds * 1e9]


def pendulum_off_upright(trace, seconds, joint="pendulum.hinge"):
    """The built-in pendulum's largest distance from upright (pi), in rad,
    over the trace's last `seconds`, and the trace's length in s."""
    steps = joint_steps(trace, joint + ".position")
    return max(abs(wrap(q[0] - math.pi)) for _, q in last(steps, seconds)), steps[-1][0] / 1e9
