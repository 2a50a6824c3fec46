"""No skip vanishes (issue 36): what a test needs and lacks here is a skip,
counted and listed per test function by tools/test_summary.py (the closing
lines of tools/bootstrap.sh test), and under CI (CI=true) a failure naming
what is missing and how to get it. Checked on both runners: the cmocka
robot_load test with ../shared/robots pointed at an empty folder (its four
published-file cases need it, its eleven others do not), and a harness.py
test file with one function that needs a tool no machine has. And a
file that dies inside a function is counted failed, not lost.

    skip_rules.py TEST_ROBOT_LOAD SOURCE_ROOT
"""

import json
import os
import subprocess
import sys
import tempfile

ROBOT_LOAD, ROOT = sys.argv[1:3]
sys.path.insert(0, os.path.join(ROOT, "tools"))
import test_summary  # noqa: E402

# test_robot_load.cc's cases that read ../shared/robots, and the others
# (9 in its first group, 6 in the malformed files' group).
PUBLISHED = ["test_acrobot", "test_cartpole", "test_vehicle", "test_double_pendulum_world"]
OTHERS = 9 + 6 - len(PUBLISHED)

PROBE = '''
from harness import main, need_tool

def test_that_needs_nothing():
    pass

def test_that_needs_a_tool_no_machine_has():
    need_tool("tcs-absent-tool", "tcs-absent-package")

main(globals())
'''

# A file that dies inside a function prints no FAILED line for it.
DYING = '''
import os
from harness import main

def test_that_passes():
    pass

def test_that_dies_inside():
    os._exit(3)

main(globals())
'''


def run(args, ci, extra_env=None):
    """args with CI=true (ci) or without CI, as meson would log them:
    (exit status, its testlog.json record)."""
    env = {k: v for k, v in os.environ.items() if k != "CI"}
    env.update(extra_env or {})
    if ci:
        env["CI"] = "true"
    p = subprocess.run(args, env=env, capture_output=True, text=True, timeout=120)
    # meson's results for an exit status (mtest: 0 OK, 77 SKIP, else FAIL),
    # and the fields its JSON log has.
    result = "OK" if p.returncode == 0 else "SKIP" if p.returncode == 77 else "FAIL"
    return p.returncode, {"name": "tcs:unit / " + os.path.basename(args[-1]), "result": result,
                          "stdout": p.stdout, "stderr": p.stderr}


def summary_of(record):
    """tools/test_summary.py's lines for a log holding that one record."""
    with tempfile.NamedTemporaryFile("w", suffix=".json") as log:
        log.write(json.dumps(record) + "\n")
        log.flush()
        return test_summary.summary(log.name)


failures = []


def check(cond, what, shown):
    print(("ok     " if cond else "FAILED ") + what)
    if not cond:
        failures.append(what)
        print("  " + "\n  ".join(shown))


with tempfile.TemporaryDirectory() as empty:
    hidden = {"TCS_SHARED_ROBOTS": empty}
    # Without CI: the four cases are skips, each listed with its reason.
    status, record = run([ROBOT_LOAD], ci=False, extra_env=hidden)
    lines = summary_of(record)
    check(status == 0, "robot_load without ../shared/robots, no CI: exits 0 (meson: OK)", [str(status)])
    check(lines[0].endswith(": %d functions passed, 0 failed, 4 skipped (in 1 test files)" % OTHERS),
          "  ... and the summary counts its 4 skipped functions", lines)
    check(all(any(l.startswith("  skipped: unit / test_robot_load %s: %s/" % (n, empty)) and "is absent" in l
                  and "../shared/robots" in l for l in lines) for n in PUBLISHED),
          "  ... and lists each with the absent file and where it belongs", lines)
    # Under CI: the same four cases fail, naming what is missing.
    status, record = run([ROBOT_LOAD], ci=True, extra_env=hidden)
    lines = summary_of(record)
    check(status != 0, "robot_load without ../shared/robots, CI=true: fails", [str(status)])
    check(lines[0].endswith(": %d functions passed, 4 failed, 0 skipped (in 1 test files)" % OTHERS) and
          all("  failed: unit / test_robot_load " + n in lines for n in PUBLISHED),
          "  ... the 4 cases that need it, and only those", lines)
    check(record["stderr"].count("is absent") == 4 and "../shared/robots" in record["stderr"],
          "  ... each saying what is absent and how to get it", [record["stderr"]])

with tempfile.TemporaryDirectory() as tmp:
    probe = os.path.join(tmp, "test_probe.py")
    with open(probe, "w") as f:
        f.write(PROBE)
    on_path = {"PYTHONPATH": os.path.join(ROOT, "tests", "process"), "PYTHONDONTWRITEBYTECODE": "1"}
    status, record = run([sys.executable, probe], ci=False, extra_env=on_path)
    lines = summary_of(record)
    check(status == 0, "a harness file, one function needing an absent tool, no CI: exits 0 (meson: OK)",
          [str(status), record["stdout"], record["stderr"]])
    check(lines == ["plain: 1 functions passed, 0 failed, 1 skipped (in 1 test files)",
                    "  skipped: unit / test_probe.py test_that_needs_a_tool_no_machine_has: tcs-absent-tool is "
                    "not installed: apt-get install tcs-absent-package (tools/bootstrap.sh test installs it)"],
          "  ... and the summary counts and lists that function's skip, with the package", lines)
    status, record = run([sys.executable, probe], ci=True, extra_env=on_path)
    lines = summary_of(record)
    check(status == 1 and "apt-get install tcs-absent-package" in record["stdout"],
          "the same under CI=true: fails, naming the package", [str(status), record["stdout"]])
    check(lines[:2] == ["plain: 1 functions passed, 1 failed, 0 skipped (in 1 test files)",
                        "  failed: unit / test_probe.py test_that_needs_a_tool_no_machine_has"],
          "  ... and the summary counts that function failed", lines)

    dying = os.path.join(tmp, "test_dying.py")
    with open(dying, "w") as f:
        f.write(DYING)
    status, record = run([sys.executable, dying], ci=False, extra_env=on_path)
    lines = summary_of(record)
    check(status == 3 and lines[:2] == ["plain: 1 functions passed, 1 failed, 0 skipped (in 1 test files)",
                                        "  failed: unit / test_dying.py (the file: FAIL after its last function)"],
          "a file that dies inside a function: the summary counts a failure", [str(status)] + lines)

sys.exit(1 if failures else 0)
