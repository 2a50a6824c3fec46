"""Revolute joint limits beyond ±π are refused (docs/DESIGN.md §8: ODE's
hinge angle wraps there), before anything starts, as every bad robot file
is: exit 2 and one line, FILE:LINE: what, the line the joint's own. A URDF
and an SDF of one moving link each, written here, with the limits a case
gives; limits within ±π load, and so do limits that take in all of it."""

import os
import re
import tempfile

from harness import check, main, scenario_file, tcs

URDF = """\
<?xml version="1.0"?>
<robot name="arm">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="upper">
    <inertial><origin xyz="0 0 -0.5"/><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/>
    <child link="upper"/>
    <axis xyz="0 1 0"/>
    <limit lower="{lower}" upper="{upper}" effort="10" velocity="10"/>
  </joint>
</robot>
"""

SDF = """\
<?xml version="1.0"?>
<sdf version="1.6">
  <model name="arm">
    <link name="base">
      <inertial><mass>1</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>
    <link name="upper">
      <pose>0 0 -0.5 0 0 0</pose>
      <inertial><mass>1</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>
    <joint name="fix" type="fixed">
      <parent>world</parent>
      <child>base</child>
    </joint>
    <joint name="shoulder" type="revolute">
      <parent>base</parent>
      <child>upper</child>
      <axis><xyz>0 1 0</xyz><limit><lower>{lower}</lower><upper>{upper}</upper></limit></axis>
    </joint>
  </model>
</sdf>
"""


def joint_lines(text):
    """The lines (from 1) from <joint name="shoulder" to its </joint>."""
    lines = text.splitlines()
    first = next(i for i, line in enumerate(lines) if 'joint name="shoulder"' in line)
    last = next(i for i in range(first, len(lines)) if "</joint>" in lines[i])
    return range(first + 1, last + 2)


def load(kind, lower, upper):
    """tcs-run of `true` on a scenario of the robot with those limits."""
    text = (URDF if kind == "urdf" else SDF).format(lower=lower, upper=upper)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "arm." + kind)
        with open(path, "w") as f:
            f.write(text)
        fixed = "fixed = true\n" if kind == "urdf" else ""
        with scenario_file('[[model]]\nname = "arm"\nfile = "%s"\n%s' % (path, fixed)) as world:
            r = tcs("-q", "-w", world, "--", "true", timeout=60)
    return r, path, joint_lines(text)


def test_revolute_limits_beyond_pi_are_refused_at_the_joints_line():
    for kind in ("urdf", "sdf"):
        for lower, upper in ((-1.0, 4.0), (-4.0, 1.0), (3.2, 3.3), (-3.3, -3.2)):
            r, path, lines = load(kind, lower, upper)
            err = r.stderr.strip().splitlines()
            m = re.match(r"tcs-run: %s:(\d+): \S" % re.escape(path), err[0]) if err else None
            check(r.returncode == 2 and len(err) == 1 and m and int(m.group(1)) in lines,
                  "%s, limits %g..%g: exit 2, one line at the joint's (%d-%d)" %
                  (kind, lower, upper, lines[0], lines[-1]), r)
            print("  %s %5g..%-5g %s" % (kind, lower, upper, err[0][len("tcs-run: ") + len(path) + 1:][:100]))


def test_revolute_limits_within_pi_load():
    """And limits that take in all of -π..π (a UR arm's ±2π), which leave the
    joint turning freely (docs/DESIGN.md §8)."""
    for kind in ("urdf", "sdf"):
        for lower, upper in ((-1.0, 1.0), (-3.14159, 3.14159), (-6.2832, 6.2832)):
            r, _, _ = load(kind, lower, upper)
            check(r.returncode == 0, "%s, limits %g..%g: loads" % (kind, lower, upper), r)


if __name__ == "__main__":
    main(globals())
