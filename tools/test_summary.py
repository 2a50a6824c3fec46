#!/usr/bin/env python3
"""The closing lines of tools/bootstrap.sh test, from meson's JSON test logs
(build/meson-logs/testlog.json, testlog-SETUP.json): test functions passed,
failed and skipped, then each skipped function with its reason (each failed
one too), so that no skip vanishes inside a test file meson calls OK.

    tools/test_summary.py LOG [LOG...]

A meson test is one file; its functions are read from what it printed:
tests/process/harness.py's "ok/FAILED/SKIP NAME" lines, or cmocka's
"[ RUN      ] NAME" followed by its "[       OK ]", "[  FAILED  ]",
"[  ERROR   ]" or "[  SKIPPED ]" line (a skip's reason is the line the test
printed last before it). Any other test is one function, the file itself.
Exit 0 (meson's own exit status says whether the suite passed), 2 if a log
cannot be read."""

import json
import os
import re
import sys

HARNESS = re.compile(r"^(ok|FAILED|SKIP) +(test_\w+)(?: +(.*))?$")
CMOCKA = re.compile(r"^\[ *(RUN|OK|FAILED|ERROR|SKIPPED) *\] (\S+)$")
CMOCKA_OUTCOME = {"OK": "passed", "FAILED": "failed", "ERROR": "failed", "SKIPPED": "skipped"}
# meson's results for a file that ended well (one without functions of its
# own counts as one function: passed, or skipped on exit 77).
MESON_OUTCOME = {"OK": "passed", "EXPECTEDFAIL": "passed", "SKIP": "skipped"}


def file_name(test):
    """A test's name without its project: 'unit / robot_load'."""
    return re.sub(r"^[^:/ ]+:", "", test["name"])


def harness_functions(lines):
    """(function, outcome, reason) from harness.py's lines."""
    out = []
    for line in lines:
        m = HARNESS.match(line)
        if m:
            kind = {"ok": "passed", "FAILED": "failed", "SKIP": "skipped"}[m.group(1)]
            out.append((m.group(2), kind, (m.group(3) or "").strip() if kind == "skipped" else ""))
    return out


def cmocka_functions(lines):
    """(function, outcome, reason) from cmocka's lines: a function's
    outcome follows its RUN line (summary lines, on stderr, are not read)."""
    out, running, said = [], None, ""
    for line in lines:
        m = CMOCKA.match(line.strip())
        if m and m.group(1) == "RUN":
            running, said = m.group(2), ""
        elif m and running == m.group(2) and m.group(1) in CMOCKA_OUTCOME:
            kind = CMOCKA_OUTCOME[m.group(1)]
            out.append((running, kind, said if kind == "skipped" else ""))
            running = None
        elif running and line.strip() and not line.startswith("["):
            said = line.strip()
    return out


def functions(test):
    """The file's functions as (function, outcome, reason). A file meson
    did not call OK or SKIP (a crash, a timeout, a failure outside any
    function) that shows no failed function fails as a whole: its last
    function began and never ended."""
    lines = (test.get("stdout") or "").splitlines()
    found = harness_functions(lines) or cmocka_functions(lines)
    result = test["result"]
    if not found:
        reason = ""
        if result == "SKIP":
            reason = (lines or ["(no reason given)"])[-1].strip()
        return [("", MESON_OUTCOME.get(result, "failed"), reason)]
    if result not in MESON_OUTCOME and not any(kind == "failed" for _, kind, _ in found):
        found.append(("(the file: %s after its last function)" % result, "failed", ""))
    return found


def summary(path):
    """The closing lines for one log."""
    tests = [json.loads(line) for line in open(path) if line.strip()]
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    listed = {"failed": [], "skipped": []}
    for test in tests:
        for fn, kind, reason in functions(test):
            counts[kind] += 1
            if kind in listed:
                where = file_name(test) + (" " + fn if fn else "")
                listed[kind].append(where + (": " + reason if reason else ""))
    setup = re.match(r"testlog-?(.*)\.json$", os.path.basename(path))
    label = (setup.group(1) if setup and setup.group(1) else "plain")
    lines = ["%s: %d functions passed, %d failed, %d skipped (in %d test files)" %
             (label, counts["passed"], counts["failed"], counts["skipped"], len(tests))]
    lines += ["  failed: " + f for f in listed["failed"]]
    lines += ["  skipped: " + s for s in listed["skipped"]] or ["  skipped: none"]
    return lines


def main(paths):
    if not paths:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    status = 0
    for path in paths:
        try:
            print("\n".join(summary(path)))
        except (OSError, ValueError, KeyError) as e:
            print("test_summary: %s: %s" % (path, e), file=sys.stderr)
            status = 2
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
