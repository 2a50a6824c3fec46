"""Worlds beyond one pendulum: two robots with two controllers at their own
rates, each on a virtual CPU of its own, and the 1000-box world whose steps
cost wildly varying wall time while the controller's virtual timing stays
exactly what it is in a cheap world."""

import os
import re

from harness import calibrate, check, main, prog, scenario_file, tcs

PD = os.path.join(os.environ.get("TCS_EXAMPLES", "."), "pendulum_pd")

TWO = """\
[sim]
step = "1ms"

[[model]]
name = "left"
type = "pendulum"
initial_angle = 3.0

[[model]]
name = "right"
type = "pendulum"
length = 1.5
mass = 2.0
initial_angle = 3.3

[[device]]
path = "/dev/tcs/left/state"
kind = "sensor"
signals = ["left.hinge.position", "left.hinge.velocity"]
rate = "1kHz"

[[device]]
path = "/dev/tcs/left/torque"
kind = "actuator"
signals = ["left.hinge.effort"]
limit = 5.0

[[device]]
path = "/dev/tcs/right/state"
kind = "sensor"
signals = ["right.hinge.position", "right.hinge.velocity"]
rate = "250Hz"

[[device]]
path = "/dev/tcs/right/torque"
kind = "actuator"
signals = ["right.hinge.effort"]
limit = 15.0

[[controller]]
command = "{pd} --rate 1000 --seconds 4 --state /dev/tcs/left/state --torque /dev/tcs/left/torque"

[[controller]]
command = "{pd} --rate 250 --seconds 4 --work-us {work} --length 1.5 --mass 2 --limit 15 --state /dev/tcs/right/state --torque /dev/tcs/right/torque"
cpu_scale = 2.0
"""


def summary_rates(r):
    """(cycles, Hz, misses) per controller, in scenario order, from the summary."""
    rows = re.findall(r"(\d+) periodic waits \(([\d.]+) Hz\), (\d+) deadline misses", r.stderr)
    return [(int(a), float(b), int(c)) for a, b, c in rows]


def run_two(work_us):
    with scenario_file(TWO.format(pd=PD, work=work_us)) as path:
        r = tcs("-w", path, timeout=120)
    check(r.returncode == 0, "both controllers run to their end", r)
    rows = summary_rates(r)
    check(len(rows) == 2, "a summary line per controller", r)
    return r, rows


def test_two_robots_keep_their_own_rates():
    r, light = run_two(100)  # the slow loop's work fits its 4 ms period
    print("  light: left %s, right %s" % (light[0], light[1]))
    check(r.stdout.count("balanced=1") == 2, "both pendulums balanced", r)
    # Each runs its loop for 4 s of its own clock (the summary's Hz also
    # counts its start-up, so count cycles).
    check(abs(light[0][0] - 4000) <= 2, "left keeps 1 kHz: %d cycles in 4 s" % light[0][0])
    check(abs(light[1][0] - 1000) <= 2, "right keeps 250 Hz: %d cycles in 4 s" % light[1][0])
    r, heavy = run_two(6000)  # 6 ms of work on a CPU twice as slow: 12 ms > 4 ms
    print("  right overloaded: left %s, right %s" % (heavy[0], heavy[1]))
    check(heavy[1][0] < 800 and heavy[1][2] > heavy[1][0] // 2, "right falls below its rate", r)
    # Its cycles are the same; misses (of 4000) can come or go with this
    # shared VM's hiccups, which are charged as CPU (they appear in either
    # run, at the commit before child processes too; 11 seen once in CI's
    # light run): up to 1 %, as for the other tests that count them.
    check(abs(heavy[0][0] - light[0][0]) <= 1 and abs(heavy[0][2] - light[0][2]) <= 0.01 * light[0][0],
          "left's timing does not change when right does heavy work", r)


def test_box_world_costs_wall_time_not_virtual_time():
    rounds = calibrate() * 3 // 10
    boxes = os.path.join(os.environ.get("TCS_SCENARIOS", "scenarios"), "boxes.toml")
    with scenario_file('[sim]\nstep = "1ms"\nmodel = "boxes"\n[model]\ncount = 1000\n') as world:
        runs = {}
        for name, args in (("pendulum", []), ("1000 boxes", ["-w", world])):
            r = tcs(*args, "-m", "lockstep", "-d", "1s", "--", prog("periodic"), "1000", "2", rounds, timeout=300)
            check(r.returncode == 0, "the run succeeds", r)
            m = re.search(r"wall cost per step min ([\d.]+ \w+), median ([\d.]+ \w+), max ([\d.]+ \w+)", r.stderr)
            check(m is not None, "the summary reports the world's step cost", r)
            runs[name] = (summary_rates(r), m.groups(), r)
            print("  %-10s world: loop %s; step wall cost min %s, median %s, max %s" %
                  ((name, runs[name][0][0]) + m.groups()))
        check(runs["pendulum"][0] == runs["1000 boxes"][0], "the controller's loop statistics are identical")

        def ns(text):
            value, unit = text.split()
            return float(value) * {"ns": 1, "us": 1e3, "ms": 1e6, "s": 1e9}[unit]
        lo, _, hi = (ns(x) for x in runs["1000 boxes"][1])
        check(hi > 1.3 * lo, "the box world's step cost varies widely (%.0f..%.0f ns)" % (lo, hi))
        check(lo > 10 * ns(runs["pendulum"][1][1]), "and is far above the pendulum's")
    check(os.path.exists(boxes), "scenarios/boxes.toml ships")


def test_shipped_scenarios_are_valid_and_two_pendulums_runs():
    folder = os.environ.get("TCS_SCENARIOS", "scenarios")
    files = sorted(f for f in os.listdir(folder) if f.endswith(".toml"))
    check({"pendulum.toml", "cartpole.toml", "double_pendulum.toml", "boxes.toml"} <= set(files),
          "a scenario per built-in model: %s" % files)
    for f in files:
        r = tcs("-w", os.path.join(folder, f), "--list-signals")
        check(r.returncode == 0 and "devices" in r.stdout, "%s is valid against the real world" % f, r)
    path = os.environ.get("TCS_EXAMPLES", ".") + ":" + os.environ.get("PATH", "")
    r = tcs("-q", "-w", os.path.join(folder, "two_pendulums.toml"), "-d", "6s", env={"PATH": path}, timeout=120)
    check(r.returncode == 0 and r.stdout.count("balanced=1") == 2, "both robots balanced", r)


if __name__ == "__main__":
    main(globals())
