"""Timer slack (docs/DESIGN.md §2): a timed wait ends its thread's timer
slack after its deadline, as on Linux: 50 us for a normal thread, what it
set with prctl(PR_SET_TIMERSLACK), none for a thread the program made
real-time; --no-slack ends every wait at its deadline. Checked exactly in
lockstep (tests/programs/slack.c), and against the machine itself with a
Python asyncio loop."""

import os
import tempfile

from harness import PYTHON, SLACK, check, main, native, prog, tcs

MS = 1000000


def spans(*options):
    r = tcs("-q", "-m", "lockstep", *options, prog("slack"), timeout=60)
    check(r.returncode == 0, "slack runs", r)
    return {k: int(v) for k, v in r.values().items()}, r


def test_waits_end_their_slack_late():
    v, r = spans()
    # Relative sleeps each end 50 us late, and the next counts from there.
    check(v["relative_ns"] == 100 * (MS + SLACK), "100 relative 1 ms sleeps: 100 x 1.05 ms", r)
    # Absolute ones do not drift: each ends 50 us after its own deadline.
    check(v["absolute_ns"] == 100 * MS + SLACK, "100 absolute 1 ms sleeps: 100 ms and the last one's 50 us", r)
    # A 2 ms pthread_cond_timedwait's timeout is a timed wait too.
    check(v["cond_2ms_ns"] == 2 * MS + SLACK, "a 2 ms condition-variable timeout ends 50 us late", r)
    # select, poll and epoll: 0.1 % of the timeout when that is more.
    check(v["poll_1s_ns"] == 1000 * MS + MS, "a 1 s poll timeout ends 1 ms (0.1 %) late", r)


def test_prctl_sets_the_slack():
    v, r = spans()
    check(v["default_slack_ns"] == SLACK and v["set_slack_ns"] == 1000 and v["reset_slack_ns"] == SLACK,
          "PR_GET_TIMERSLACK: 50 us, then the 1 us set, then 50 us again after PR_SET_TIMERSLACK 0", r)
    check(v["relative_1us_ns"] == 100 * (MS + 1000), "with 1 us of slack: 100 x 1.001 ms", r)


def test_real_time_threads_have_none():
    # Made real-time by the program (not by tcs, which runs every
    # controller SCHED_FIFO where it may): a thread created so, and the
    # main thread while it is; normal again, 50 us again.
    v, r = spans()
    check(v["rt_thread_relative_ns"] == 100 * MS, "a thread created SCHED_FIFO: 100 sleeps of exactly 1 ms", r)
    check(v["rt_main_relative_ns"] == 100 * MS, "the main thread made SCHED_FIFO: 100 sleeps of exactly 1 ms", r)
    check(v["normal_again_relative_ns"] == 100 * (MS + SLACK), "SCHED_OTHER again: 50 us a sleep", r)


def test_no_slack_is_exact():
    v, r = spans("--no-slack")
    for name, ns in (("relative_ns", 100 * MS), ("absolute_ns", 100 * MS), ("relative_1us_ns", 100 * MS),
                     ("poll_1s_ns", 1000 * MS), ("cond_2ms_ns", 2 * MS)):
        check(v[name] == ns, "--no-slack: %s is exactly %d ns" % (name, ns), r)
    # What the program reads of its slack is still what it set.
    check(v["set_slack_ns"] == 1000, "--no-slack: prctl still reports what was set", r)


ASYNCIO = """
import asyncio, time
async def main():
    t0 = time.monotonic()
    for _ in range(200):
        await asyncio.sleep(0.01)
    print("elapsed_s=%.9f" % (time.monotonic() - t0))
asyncio.run(main())
"""


def test_asyncio_paces_as_natively():
    # 200 asyncio.sleep(0.01): an epoll_wait of 10 ms each (its timeout
    # rounded up to whole ms), and its slack. Ended exactly at deadlines,
    # lockstep once made it 11 ms a cycle (2.2 s); natively it is about
    # 10.2 ms (the slack and the machine's own latency).
    with tempfile.TemporaryDirectory(prefix="tcs-test-slack-") as d:
        script = os.path.join(d, "aio.py")
        with open(script, "w") as f:
            f.write(ASYNCIO)
        r = tcs("-q", "-m", "lockstep", "--", PYTHON, script, timeout=60)
        check(r.returncode == 0, "the asyncio loop runs", r)
        lockstep = float(r.values()["elapsed_s"])
        natives = []
        for _ in range(3):
            n = native([PYTHON, script], timeout=60)
            check(n.returncode == 0, "the asyncio loop runs natively", n)
            natives.append(float(n.values()["elapsed_s"]))
    nat = sorted(natives)[1]
    print("  200 x asyncio.sleep(0.01): %.6f s in lockstep, %.6f s natively (median of %s)" % (lockstep, nat, natives))
    check(2.0 + 200 * SLACK / 1e9 <= lockstep, "each cycle at least 10 ms and its slack: %.6f s" % lockstep, r)
    check(abs(lockstep - nat) <= 0.03 * nat, "within 3 %% of the native pace: %.6f s, %.6f s" % (lockstep, nat), r)


if __name__ == "__main__":
    main(globals())
