"""The two-wheeled robot example (examples/diffdrive) under tcs-run: an SDF
world of the project's own (a floor and a differential-drive robot
simulated together), its pose and wheel speeds read at 100 Hz by a plain
Python controller that drives its wheel motors to a waypoint. What a user
of it relies on: that it gets there and stays, in both modes, and that
the robot rolls on the floor as a robot does (neither sinking into it nor
hopping, no faster than its wheels turn). Where it went is read from the
run's trace, not from the controller's verdict: the trace's world state
(/tcs/step) holds the joints, not the chassis's pose, so the path is the
one its wheels rolled (odometry from their angles: rolled)."""

import math
import os
import tempfile

from harness import PYTHON, check, main, tcs
from world_trace import joint_steps

EXAMPLE = os.path.join(os.environ.get("TCS_EXAMPLES_SRC", "examples"), "diffdrive")
SCENARIO = os.path.join(EXAMPLE, "diffdrive.toml")
CONTROLLER = os.path.join(EXAMPLE, "waypoint.py")
GOAL = (2.0, 1.0)
# The chassis frame's height at rest (diffdrive.sdf): the wheels' axle, a
# wheel radius above the floor.
REST_Z = 0.05
# waypoint.py's top speed, m/s.
V_MAX = 0.4
# The wheels (diffdrive.sdf): radius, and the track between their contacts.
WHEEL_RADIUS, TRACK = 0.05, 0.25
WHEELS = ("w.robot.left_wheel_joint.position", "w.robot.right_wheel_joint.position")


def rolled(steps):
    """The chassis's path as its wheels rolled it, from the origin facing x
    (diffdrive.sdf's pose): (s, x, y) at every step, each step's arc from
    the two wheels' turns (forward: their mean; turning: their difference
    over the track)."""
    x = y = heading = 0.0
    left = right = 0.0
    path = []
    for v, (a, b) in steps:
        dl, dr = (a - left) * WHEEL_RADIUS, (b - right) * WHEEL_RADIUS
        left, right = a, b
        ds, turn = (dl + dr) / 2, (dr - dl) / TRACK
        x += ds * math.cos(heading + turn / 2)
        y += ds * math.sin(heading + turn / 2)
        heading += turn
        path.append((v / 1e9, x, y))
    return path


def test_the_robot_drives_to_its_waypoint_and_stays():
    # 15 s: it comes within 0.1 m at about 6 s and stops at about 7.3 s;
    # the rest of the run shows that it stays.
    for mode in ("lockstep", "cpu"):
        with tempfile.TemporaryDirectory() as tmp:
            trace = os.path.join(tmp, "run.mcap")
            r = tcs("-q", "-m", mode, "--seed", "1", "-w", SCENARIO, "-d", "15s", "-t", trace, "--",
                    PYTHON, CONTROLLER, str(GOAL[0]), str(GOAL[1]), timeout=180)
            v = r.values()
            check(r.returncode == 0 and "reached_at" in v, "%s: the example runs and reports" % mode, r)
            path = rolled(joint_steps(trace, *WHEELS))
        off = [(t, math.hypot(x - GOAL[0], y - GOAL[1])) for t, x, y in path]
        reached = next((t for t, d in off if d < 0.1), -1)
        check(0 < reached < 10, "%s: within 0.1 m of the waypoint by 10 s (at %.3f s)" % (mode, reached), r)
        # At most its top speed from the start (the origin) to 0.1 m short
        # of the waypoint.
        least = (math.hypot(*GOAL) - 0.1) / V_MAX
        check(reached >= least, "%s: no sooner than its top speed allows (%.2f s; at %.2f s)" % (mode, least, reached), r)
        worst = max(d for t, d in off if t >= 11)
        check(path[-1][0] == 15 and worst < 0.1,
              "%s: there from 11 s to the run's end at %.3f s, at most %.4f m from it, %.4f m at the end" %
              (mode, path[-1][0], worst, off[-1][1]), r)
        # The robot's own report: where it stopped, and its chassis's height
        # as its pose sensor read it (the trace has no link poses).
        stopped, z_min, z_max = float(v["stopped_at"]), float(v["z_min"]), float(v["z_max"])
        check(0 < stopped < 11, "%s: it says it stopped there by 11 s (at %s s)" % (mode, v["stopped_at"]), r)
        check(abs(z_min - REST_Z) < 0.003 and abs(z_max - REST_Z) < 0.003,
              "%s: the chassis rides at its rest height %.3f m within 3 mm while driving (%.6f to %.6f m)" %
              (mode, REST_Z, z_min, z_max), r)
        print("  %-8s rolled within 0.1 m at %.2f s, at most %.4f m off from 11 s, %.4f m at the end (it says %s m); "
              "stopped at %.2f s; chassis z %.6f to %.6f m" % (mode, reached, worst, off[-1][1], v["distance"], stopped,
                                                               z_min, z_max))


if __name__ == "__main__":
    main(globals())
