"""The two-wheeled robot example (examples/diffdrive) under tcs-run: an SDF
world of the project's own (a floor and a differential-drive robot
simulated together), its pose and wheel speeds read at 100 Hz by a plain
Python controller that drives its wheel motors to a waypoint. What a user
of it relies on: that it gets there and stays, in both modes, and that
the robot rolls on the floor as a robot does (neither sinking into it nor
hopping, no faster than its wheels turn)."""

import math
import os

from harness import PYTHON, check, main, tcs

EXAMPLE = os.path.join(os.environ.get("TCS_EXAMPLES_SRC", "examples"), "diffdrive")
SCENARIO = os.path.join(EXAMPLE, "diffdrive.toml")
CONTROLLER = os.path.join(EXAMPLE, "waypoint.py")
GOAL = (2.0, 1.0)
# The chassis frame's height at rest (diffdrive.sdf): the wheels' axle, a
# wheel radius above the floor.
REST_Z = 0.05
# waypoint.py's top speed, m/s.
V_MAX = 0.4


def test_the_robot_drives_to_its_waypoint_and_stays():
    # 15 s: it comes within 0.1 m at about 6 s and stops at about 7.3 s;
    # the rest of the run shows that it stays.
    for mode in ("lockstep", "cpu"):
        r = tcs("-q", "-m", mode, "--seed", "1", "-w", SCENARIO, "-d", "15s", "--",
                PYTHON, CONTROLLER, str(GOAL[0]), str(GOAL[1]), timeout=180)
        v = r.values()
        check(r.returncode == 0 and "reached_at" in v, "%s: the example runs and reports" % mode, r)
        reached, distance = float(v["reached_at"]), float(v["distance"])
        stopped, worst = float(v["stopped_at"]), float(v["worst_after_stop"])
        z_min, z_max = float(v["z_min"]), float(v["z_max"])
        check(0 < reached < 10, "%s: within 0.1 m of the waypoint by 10 s (at %s s)" % (mode, v["reached_at"]), r)
        # At most its top speed from the start (the origin) to 0.1 m short
        # of the waypoint: a robot faster than its wheels turn would slide.
        least = (math.hypot(*GOAL) - 0.1) / V_MAX
        check(reached >= least, "%s: no sooner than its top speed allows (%.2f s; at %.2f s)" % (mode, least, reached), r)
        check(0 < stopped < 11 and worst < 0.1 and distance < 0.1,
              "%s: stopped there by 11 s (at %s s), at most %s m from it since, %s m at the end" %
              (mode, v["stopped_at"], v["worst_after_stop"], v["distance"]), r)
        check(abs(z_min - REST_Z) < 0.003 and abs(z_max - REST_Z) < 0.003,
              "%s: the chassis rides at its rest height %.3f m within 3 mm while driving (%.6f to %.6f m)" %
              (mode, REST_Z, z_min, z_max), r)
        print("  %-8s within 0.1 m at %.2f s, stopped at %.2f s, at most %.4f m off since, %.4f m at the end; "
              "chassis z %.6f to %.6f m" % (mode, reached, stopped, worst, distance, z_min, z_max))


if __name__ == "__main__":
    main(globals())
