"""Robots from URDF and SDF files (docs/DESIGN.md §8) under tcs-run: the
published descriptions in ../shared/robots load (when that folder is
there: a user's clone has none) and the project's own in tests/robots
everywhere; their physics checked against analysis, not against
itself; stock programs read their devices; bad files are refused before
anything starts with FILE:LINE and exit 2."""

import math
import os
import re
import tempfile
import xml.etree.ElementTree as ET

from harness import check, main, missing, scenario_file, tcs
from world_trace import joint_steps, last, wrap

HERE = os.path.dirname(os.path.abspath(__file__))
OWN = os.path.join(HERE, "..", "robots")
SHARED = os.path.normpath(os.path.join(HERE, "..", "..", "..", "shared", "robots"))
PUBLISHED = {"Acrobot.urdf": ["shoulder", "elbow"], "cartpole.urdf": ["slider_to_cart", "cart_to_pole"],
             "vehicle_model.sdf": ["left_wheel_joint", "right_wheel_joint"],
             "double_pendulum_model.sdf": ["double_pendulum_with_base0.upper_joint",
                                           "double_pendulum_with_base0.lower_joint"]}


# How to get ../shared/robots (the C side, tests/unit/test_robot_load.cc,
# says the same).
SHARED_HOW = ("the published robot files are read from ../shared/robots beside the project: put that folder "
              "there (its SOURCES.md names each file's upstream repository and commit)")


def shared(name):
    path = os.path.join(SHARED, name)
    if not os.path.exists(path):
        missing("%s is absent" % path, SHARED_HOW)
    return path


def model(path, name="r", extra=""):
    return '[[model]]\nname = "%s"\nfile = "%s"\n%s' % (name, path, extra)


def stream(path, signals, rate="1kHz"):
    return '[[device]]\npath = "%s"\nkind = "sensor"\nsignals = [%s]\nrate = "%s"\n' % (
        path, ", ".join('"%s"' % s for s in signals), rate)


def records(world, n, device="/dev/tcs/s", *options):
    with scenario_file(world) as w:
        r = tcs("-q", "-m", "lockstep", *options, "-w", w, "--", "head", "-n", str(n), device, timeout=120)
    check(r.returncode == 0, "head reads %s" % device, r)
    rows = [[float(x) for x in line.split()] for line in r.stdout.splitlines()]
    check(len(rows) == n, "head printed %d records" % n, r)
    return rows


def test_the_published_robots_load_with_their_joints():
    for name, joints in PUBLISHED.items():
        path = shared(name)
        with scenario_file(model(path)) as w:
            r = tcs("--list-signals", "-w", w, timeout=60)
        check(r.returncode == 0, "%s loads" % name, r)
        for j in joints:
            for field, unit in (("position", "rad|m"), ("velocity", "rad/s|m/s"), ("effort", "N")):
                check(re.search(r"r\.%s\.%s\s+1 value\s+(%s)" % (re.escape(j), field, unit), r.stdout),
                      "%s: --list-signals names %s.%s with its unit" % (name, j, field), r)
        print("  %-26s %d signals, joints %s" % (name, r.stdout.count("value"), ", ".join(joints)))


# The acrobot of the project's own example, the same layout as Drake's
# Acrobot.urdf: what runs everywhere, where the published file may be absent.
OWN_ACROBOT = os.path.join(os.environ.get("TCS_EXAMPLES_SRC", "examples"), "acrobot", "acrobot.urdf")


def acrobots():
    """Drake's Acrobot.urdf if ../shared/robots is there, and the example's."""
    found = [OWN_ACROBOT]
    if os.path.exists(os.path.join(SHARED, "Acrobot.urdf")):
        found.insert(0, os.path.join(SHARED, "Acrobot.urdf"))
    else:
        print("  (%s is absent: the example's acrobot only)" % SHARED)
    return found


def drake_acrobot_checked_too():
    """After a test's checks of the acrobots(): without Drake's they were
    made on the example's alone, which is no pass of the published file
    (missing(): a skip, listed, or a failure under CI)."""
    shared("Acrobot.urdf")


def test_stock_programs_read_a_robots_devices():
    # Released from 0.2 and 0.1 rad, so that it swings: record k, due at
    # k ms, is the world at the end of step k as the trace has it (the
    # first, at 0, the release), every value to its last bit (%.17g).
    path = acrobots()[0]
    signals = ["r.shoulder.position", "r.elbow.position", "r.shoulder.velocity", "r.elbow.velocity"]
    world = model(path, extra="initial_positions = { shoulder = 0.2, elbow = 0.1 }\n") + \
        stream("/dev/tcs/acrobot/state", signals)
    with tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "run.mcap")
        rows = records(world, 3000, "/dev/tcs/acrobot/state", "-t", trace)
        steps = dict((v, q) for v, q in joint_steps(trace, *signals))
    world_at = [[0.2, 0.1, 0.0, 0.0]] + [steps.get(k * 1000000) for k in range(1, 3000)]
    wrong = [(k, row, world_at[k]) for k, row in enumerate(rows) if row != world_at[k]]
    check(not wrong, "3000 records, each the world's four values at its time: %d differ, the first %s" %
          (len(wrong), wrong[:1]))
    print("  head -n 3000 /dev/tcs/acrobot/state: 3000 records, the world's state at each ms")
    drake_acrobot_checked_too()


def urdf_acrobot(path):
    """An acrobot's parameters as its file gives them: masses, centres of
    mass along the links, inertias about the joint axis (y), damping, and
    the upper link's length (the elbow's offset)."""
    root = ET.parse(path).getroot()
    links = {l.get("name"): l for l in root.findall("link")}
    joints = {j.get("name"): j for j in root.findall("joint")}

    def inertial(link):
        i = links[link].find("inertial")
        return (float(i.find("mass").get("value")), -float(i.find("origin").get("xyz").split()[2]),
                float(i.find("inertia").get("iyy")))

    m1, lc1, I1 = inertial("upper_link")
    m2, lc2, I2 = inertial("lower_link")
    l1 = -float(joints["elbow"].find("origin").get("xyz").split()[2])
    b1 = float(joints["shoulder"].find("dynamics").get("damping"))
    b2 = float(joints["elbow"].find("dynamics").get("damping"))
    return m1, m2, l1, lc1, lc2, I1, I2, b1, b2


def acrobot_motion(p, x, seconds, dt, g=9.81):
    """The acrobot's equations of motion (Spong's, angles from hanging,
    torques zero, joint damping), integrated with RK4: x at every dt."""
    m1, m2, l1, lc1, lc2, Ic1, Ic2, b1, b2 = p
    I1, I2 = Ic1 + m1 * lc1 ** 2, Ic2 + m2 * lc2 ** 2

    def f(x):
        q1, q2, w1, w2 = x
        c2, s2 = math.cos(q2), math.sin(q2)
        M11 = I1 + I2 + m2 * l1 ** 2 + 2 * m2 * l1 * lc2 * c2
        M12 = I2 + m2 * l1 * lc2 * c2
        M22 = I2
        k = m2 * l1 * lc2 * s2
        h1 = (2 * k * w1 * w2 + k * w2 ** 2 - m1 * g * lc1 * math.sin(q1)
              - m2 * g * (l1 * math.sin(q1) + lc2 * math.sin(q1 + q2)) - b1 * w1)
        h2 = -k * w1 ** 2 - m2 * g * lc2 * math.sin(q1 + q2) - b2 * w2
        det = M11 * M22 - M12 ** 2
        return [w1, w2, (M22 * h1 - M12 * h2) / det, (M11 * h2 - M12 * h1) / det]

    out = [list(x)]
    sub = 10
    h = dt / sub
    for _ in range(int(round(seconds / dt))):
        for _ in range(sub):
            k1 = f(x)
            k2 = f([a + h / 2 * b for a, b in zip(x, k1)])
            k3 = f([a + h / 2 * b for a, b in zip(x, k2)])
            k4 = f([a + h * b for a, b in zip(x, k3)])
            x = [a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(x, k1, k2, k3, k4)]
        out.append(list(x))
    return out


def test_the_acrobot_follows_its_equations_of_motion():
    # Released from 0.2 rad at the shoulder and 0.1 rad at the elbow, the
    # simulated Acrobot.urdf and an integration of its equations written
    # here from the file's parameters agree over 3 s.
    for path in acrobots():
        params = urdf_acrobot(path)
        world = (model(path, extra="initial_positions = { shoulder = 0.2, elbow = 0.1 }\n") +
                 stream("/dev/tcs/s", ["r.shoulder.position", "r.elbow.position"]))
        rows = records(world, 3001)
        expected = acrobot_motion(params, [0.2, 0.1, 0, 0], 3.0, 0.001)
        errors = [(row[0] - e[0]) ** 2 + (row[1] - e[1]) ** 2 for row, e in zip(rows, expected)]
        rms = math.sqrt(sum(errors) / (2 * len(errors)))
        low = min(row[0] for row in rows)
        name = os.path.basename(path)
        check(low < -0.1, "%s: it swings (the shoulder through %.2f rad)" % (name, low))
        check(rms < 0.02, "%s: RMS %.5f rad from the equations over 3 s (at most 0.02)" % (name, rms))
        print("  %s against its equations of motion: RMS %.5f rad over 3 s (params %s)" %
              (name, rms, ", ".join("%g" % v for v in params)))
    drake_acrobot_checked_too()


COMPOUND = """<?xml version="1.0"?>
<robot name="compound">
  <link name="world"/>
  <link name="body">
    <inertial>
      <origin xyz="0 0 -%(d)g" rpy="0.3 0.2 0.1"/>
      <mass value="%(m)g"/>
      <inertia ixx="%(i)g" iyy="%(i)g" izz="%(i)g" ixy="0" ixz="0" iyz="0"/>
    </inertial>
  </link>
  <joint name="pivot" type="continuous">
    <parent link="world"/>
    <child link="body"/>
    <axis xyz="1 0 0"/>
  </joint>
</robot>
"""


def test_a_compound_pendulum_swings_with_its_period():
    # A body of mass m whose centre of mass hangs d below a hinge, with an
    # inertia I_c about it (spherical: the same about any axis, so the
    # rotated inertial frame changes nothing): T = 2 pi sqrt(I / (m g d)),
    # I = I_c + m d^2, at a small amplitude (0.05 rad: 0.016 % longer).
    m, d, ic = 3.0, 0.4, 0.2
    fd, path = tempfile.mkstemp(suffix=".urdf", prefix="tcs-test-robot-")
    with os.fdopen(fd, "w") as f:
        f.write(COMPOUND % {"d": d, "m": m, "i": ic})
    try:
        world = model(path, extra="initial_positions = { pivot = 0.05 }\n") + stream("/dev/tcs/s", ["r.pivot.position"])
        rows = records(world, 10001)
    finally:
        os.unlink(path)
    angles = [row[0] for row in rows]
    # Upward zero crossings, interpolated within the step.
    ups = [k - 1 + -angles[k - 1] / (angles[k] - angles[k - 1]) for k in range(1, len(angles))
           if angles[k - 1] < 0 <= angles[k]]
    period = (ups[-1] - ups[0]) / (len(ups) - 1) * 0.001
    expected = 2 * math.pi * math.sqrt((ic + m * d * d) / (m * 9.81 * d))
    check(len(ups) >= 5, "it swings: %d periods in 10 s" % (len(ups) - 1))
    check(abs(period / expected - 1) < 0.005, "period %.5f s, expected %.5f s (0.5 %%)" % (period, expected))
    print("  compound pendulum from a URDF: period %.5f s, 2 pi sqrt(I/(m g d)) = %.5f s (%+.3f %%)" %
          (period, expected, 100 * (period / expected - 1)))


BOX = """<?xml version="1.0"?>
<robot name="box">
  <link name="body">
    <inertial><mass value="2"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
</robot>
"""


def test_a_scenarios_pose_and_fixed_place_the_robot():
    # pose = [x, y, z, roll, pitch, yaw] puts the root link there (rotations
    # about the fixed x, then y, then z axes, as URDF's rpy); fixed = true
    # holds it, without it the body falls under gravity.
    fd, path = tempfile.mkstemp(suffix=".urdf", prefix="tcs-test-robot-")
    with os.fdopen(fd, "w") as f:
        f.write(BOX)
    pose = [1.0, 2.0, 3.0, 0.1, 0.2, 0.3]
    try:
        placed = "pose = [%s]\n" % ", ".join(str(v) for v in pose)
        held = records(model(path, extra=placed + "fixed = true\n") + stream("/dev/tcs/s", ["r.body.pose"]), 500)
        free = records(model(path, extra=placed) + stream("/dev/tcs/s", ["r.body.pose"]), 500)
    finally:
        os.unlink(path)
    r, p, y = (v / 2 for v in pose[3:])
    q = [math.cos(r) * math.cos(p) * math.cos(y) + math.sin(r) * math.sin(p) * math.sin(y),
         math.sin(r) * math.cos(p) * math.cos(y) - math.cos(r) * math.sin(p) * math.sin(y),
         math.cos(r) * math.sin(p) * math.cos(y) + math.sin(r) * math.cos(p) * math.sin(y),
         math.cos(r) * math.cos(p) * math.sin(y) - math.sin(r) * math.sin(p) * math.cos(y)]
    check(all(max(abs(a - b) for a, b in zip(row, pose[:3] + q)) < 1e-9 for row in held),
          "fixed: the body stays at %s: %s" % (pose[:3] + q, held[-1]))
    # Free: it falls, record k (at k ms) as ODE's semi-implicit Euler steps
    # g t^2 / 2: z0 - g dt^2 k (k + 1) / 2 (1.2 m in 0.5 s).
    k = len(free) - 1
    expected = 3.0 - 9.81 * 1e-6 * k * (k + 1) / 2
    check(abs(free[-1][2] - expected) < 1e-6, "free: it falls, z %.6f at %d ms (%.6f)" % (free[-1][2], k, expected))
    print("  pose and fixed: held at %s; free fell to z = %.4f in %d ms" % (held[-1][:3], free[-1][2], k))


def test_a_world_files_step():
    # tests/robots/world.sdf has a 2 ms step: a scenario without a step of
    # its own takes it (500 steps a second); with one, its own.
    path = os.path.join(OWN, "world.sdf")
    for given, steps in (("", 500), ('[sim]\nstep = "1ms"\n', 1000)):
        with scenario_file(given + model(path)) as w:
            r = tcs("-m", "lockstep", "-d", "1s", "-w", w, "--", "sleep", "1", timeout=60)
        m = re.search(r"world: (\d+) steps", r.stderr)
        check(r.returncode == 0 and m and int(m.group(1)) == steps,
              "%s: %d steps in 1 s" % ("the file's step" if not given else "the scenario's step", steps), r)
    print("  world.sdf: 500 steps a second of its own, 1000 with [sim] step = \"1ms\"")


def test_an_imu_at_rest_reads_gravity_upward():
    path = os.path.join(OWN, "compound_pendulum.urdf")
    world = model(path) + stream("/dev/tcs/s", ["r.bob_imu.linear_acceleration", "r.bob_imu.angular_velocity"])
    rows = records(world, 100)
    check(all(abs(row[0]) < 1e-6 and abs(row[1]) < 1e-6 and abs(row[2] - 9.81) < 1e-6 for row in rows),
          "the hanging bob's IMU reads (0, 0, +9.81) m/s^2: %s" % rows[-1][:3])
    check(all(max(abs(v) for v in row[3:]) < 1e-9 for row in rows), "and turns at 0 rad/s")
    print("  IMU at rest: %s m/s^2" % " ".join("%.4f" % v for v in rows[-1][:3]))


def test_bad_robot_files_are_refused_with_their_line():
    cases = {"truncated.urdf": None, "nan_mass.urdf": 5, "zero_inertia.urdf": None, "loop.urdf": None,
             "unknown_link.urdf": None, "revolute2.sdf": None, "truncated.sdf": None}
    for name, line in cases.items():
        path = os.path.join(OWN, "bad", name)
        with scenario_file(model(path)) as w:
            r = tcs("-w", w, "--", "true", timeout=60)
        first = r.stderr.strip().splitlines()[0] if r.stderr.strip() else ""
        check(r.returncode == 2, "%s: exit 2" % name, r)
        check(re.match(r"tcs-run: %s:\d+: \S" % re.escape(path), first) and len(r.stderr.strip().splitlines()) == 1,
              "%s: one line, FILE:LINE: what" % name, r)
        if line:
            check(first.startswith("tcs-run: %s:%d: " % (path, line)), "%s: at line %d" % (name, line), r)
        print("  %-18s %s" % (name, first[len("tcs-run: ") + len(path) + 1:][:90]))
    with scenario_file(model("/nonexistent/robot.urdf")) as w:
        r = tcs("-w", w, "--", "true", timeout=60)
    check(r.returncode == 2 and "/nonexistent/robot.urdf: No such file or directory" in r.stderr,
          "a missing file is named", r)


def test_the_acrobot_example_swings_up_and_balances():
    # examples/acrobot: its scenario (a URDF of the project's own, noisy
    # quantised encoders at 500 Hz) and its plain C controller, in both
    # modes: up within 7 s, within 0.05 rad of upright over the last second.
    # Judged by the world in the run's trace (the controller's own verdict
    # rests on its noisy encoders): upright when both links point up (the
    # shoulder at pi, the elbow at 0), as the example measures it.
    examples = os.environ.get("TCS_EXAMPLES", "examples")
    scenario = os.path.join(os.environ.get("TCS_EXAMPLES_SRC", "examples"), "acrobot", "acrobot.toml")
    env = dict(os.environ, PATH=examples + os.pathsep + os.environ.get("PATH", ""))
    for mode in ("lockstep", "cpu"):
        with tempfile.TemporaryDirectory() as tmp:
            trace = os.path.join(tmp, "run.mcap")
            r = tcs("-q", "-m", mode, "--seed", "1", "-w", scenario, "-d", "8s", "-t", trace, timeout=120, env=env)
            v = r.values()
            check(r.returncode == 0 and "upright_at" in v, "%s: the example runs" % mode, r)
            steps = joint_steps(trace, "acrobot.shoulder.position", "acrobot.elbow.position")
        off = [(t, max(abs(wrap(q[0] - math.pi)), abs(wrap(q[0] + q[1] - math.pi)))) for t, q in steps]
        up = next((t / 1e9 for t, x in off if x < 0.1), -1)
        worst = max(x for _, x in last(off, 1))
        check(steps[-1][0] == 8000000000 and 0 < up < 7 and worst < 0.05,
              "%s: in the world up at %.3f s, at most %.4f rad off over the last second of %.3f s" %
              (mode, up, worst, steps[-1][0] / 1e9), r)
        print("  %-8s acrobot up at %.3f s, within %.4f rad of upright over the last second (it says %s s, %s rad)" %
              (mode, up, worst, v["upright_at"], v["worst_last_second"]))


if __name__ == "__main__":
    main(globals())
