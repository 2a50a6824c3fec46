"""Traces (DESIGN.md §6): tcs-run --trace writes an MCAP file that the
official reader (@mcap/core, with Node.js) reads message by message, every
channel with a schema; after a SIGKILL midway everything but the last chunk
is still there."""

import json
import os
import signal
import subprocess
import time

from harness import TCS_RUN, assert_nothing_left, check, main, run, start, tcs

PD = os.path.join(os.environ.get("TCS_EXAMPLES", "."), "pendulum_pd")
CHECK = os.environ.get("TCS_MCAP_CHECK", "tests/mcap/check.mjs")
TCS_TRACE = os.environ.get("TCS_TRACE", "tcs-trace")


def read_trace(path, complete=True):
    args = ["node", CHECK] + (["--complete"] if complete else []) + [path]
    r = subprocess.run(args, capture_output=True, text=True, timeout=120)
    check(r.returncode == 0, "the official MCAP reader reads %s: %s%s" % (path, r.stdout, r.stderr))
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_trace_of_a_pendulum_run():
    path = "/tmp/tcs-test-trace-%d.mcap" % os.getpid()
    try:
        r = tcs("-q", "-t", path, "--", PD, "--seconds", "2", timeout=60)
        check(r.returncode == 0, "the traced run succeeds", r)
        t = read_trace(path)
        print("  %d messages, %d bytes: %s" % (t["messages"], os.path.getsize(path), t["topics"]))
        check(t["channels"] == t["schemas"] == 6, "six topics, each with its schema", r)
        topics = t["topics"]
        check(topics["/tcs/controller"] == 1, "the controller described once")
        check(topics["/tcs/step"] == topics["/clock"] >= 2000, "a step and a clock message per step")
        check(abs(topics["/tcs/wait"] - 2000) <= 2, "a wait per control cycle")
        check(abs(topics["/tcs/device"] - 2000) <= 2, "a command per control cycle")
        check(topics["/tcs/slice"] >= topics["/tcs/wait"], "slices")
    finally:
        if os.path.exists(path):
            os.unlink(path)


def test_trace_survives_sigkill():
    path = "/tmp/tcs-test-killed-%d.mcap" % os.getpid()
    try:
        p = start([TCS_RUN, "-q", "-m", "lockstep", "-t", path, "--", PD])
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and (not os.path.exists(path) or os.path.getsize(path) < 300000):
            time.sleep(0.05)
        os.kill(p.pid, signal.SIGKILL)
        p.communicate(timeout=10)
        assert_nothing_left(p.pid, grace=1.0)
        t = read_trace(path, complete=False)
        print("  killed after %d bytes: %d messages readable" % (os.path.getsize(path), t["messages"]))
        check(t["messages"] > 1000 and t["truncated"], "all but the last chunk is readable")
        r = run([TCS_TRACE, "summary", "--json", path])
        check(r.returncode == 0, "tcs-trace summarises it", r)
        s = json.loads(r.stdout)
        check(s["truncated"] and s["controllers"][0]["cycles"] > 100, "as far as it goes", r)
    finally:
        if os.path.exists(path):
            os.unlink(path)


if __name__ == "__main__":
    main(globals())
