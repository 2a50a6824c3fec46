"""Edges of the hook surface (tcs-run(1), WHAT IS VIRTUALISED; docs/DESIGN.md
§2 and §3), each checked against the kernel's own answer (a native run of
the same program) and, for times, exactly in lockstep against the
contract's arithmetic: the deadline and the timer slack (50 us for a normal
thread's sleeps and futex waits; for poll, the larger of that and 0.1 % of
the timeout; none for timerfds). --spin-cost 0 keeps clock reads free, so a
span is its waits alone.
- io_uring_setup through syscall() fails with ENOSYS, said once;
- futex waits with a timeout through syscall(SYS_futex) end at the virtual
  deadline and its slack (relative, absolute, on CLOCK_REALTIME), or when
  another thread wakes them;
- poll and ppoll on sets over 256 fds (re-checked each step, not
  mirrored): the timeout is virtual, and a fd made ready is reported (by
  the step after it became ready);
- at most 64 timerfds at a time: the 65th fails with EMFILE, said once."""

from harness import SLACK, check, main, native, prog, tcs

MS = 1000000
# --epoch's CLOCK_MONOTONIC origin (docs/DESIGN.md §2, Clocks).
EPOCH_MONOTONIC = 100000 * 10**9
STEP = MS  # the built-in scenario's step


def lockstep(*args, options=()):
    r = tcs("-q", "-m", "lockstep", "--spin-cost", "0", "--epoch", "0", *options, "--", *args, timeout=60)
    check(r.returncode == 0, "%s runs in lockstep" % args[0], r)
    return r.values(), r


def test_io_uring_setup_fails_with_enosys_said_once():
    n = native([prog("io_uring_probe")])
    check(n.returncode == 0, "io_uring_probe runs natively", n)
    print("  natively: %s" % " ".join("%s=%s" % kv for kv in sorted(n.values().items())))
    for mode in ("cpu", "lockstep"):
        r = tcs("-m", mode, prog("io_uring_probe"), timeout=60)
        v = r.values()
        check(r.returncode == 0 and all(v.get("call%d_ret" % i) == "-1" and v.get("call%d_errno" % i) == "ENOSYS"
                                        for i in (1, 2)),
              "%s: both io_uring_setup calls fail with ENOSYS" % mode, r)
        check(r.stderr.count("io_uring refused (ENOSYS)") == 1, "%s: said once, for two calls" % mode, r)


def test_futex_timeouts_are_virtual():
    n = native([prog("futex_wait")]).values()
    for slack, options in ((SLACK, ()), (0, ("--no-slack",))):
        v, r = lockstep(prog("futex_wait"), options=options)
        what = "--no-slack" if options else "default slack"
        # What each call returned is the kernel's answer natively.
        for name in ("relative", "absolute", "realtime", "changed", "woken"):
            check((v["%s_ret" % name], v["%s_errno" % name]) == (n["%s_ret" % name], n["%s_errno" % name]),
                  "%s: %s returns as natively (%s %s)" % (what, name, n["%s_ret" % name], n["%s_errno" % name]), r)
        check(v["relative_errno"] == "ETIMEDOUT" and v["woken_ret"] == "0", "timed out, and woken", r)
        check(int(v["relative_ns"]) == 2 * MS + slack, "%s: FUTEX_WAIT for 2 ms ends at 2 ms + %d ns" % (what, slack),
              r)
        # Absolute deadlines 3 and 4 ms after a clock read: the read is
        # free (--spin-cost 0), so the wait lasts exactly that and its slack.
        check(int(v["absolute_ns"]) == 3 * MS + slack,
              "%s: FUTEX_WAIT_BITSET to a CLOCK_MONOTONIC deadline 3 ms on: 3 ms + %d ns" % (what, slack), r)
        check(int(v["realtime_ns"]) == 4 * MS + slack,
              "%s: FUTEX_CLOCK_REALTIME to a deadline 4 ms on: 4 ms + %d ns" % (what, slack), r)
        check(int(v["changed_ns"]) == 0, "%s: a word that changed returns EAGAIN at once" % what, r)
        # Woken by the other thread, which slept 1 ms (and its slack) from
        # the same start: the wait ends then, not at its 10 ms timeout.
        check(int(v["woken_ns"]) == MS + slack,
              "%s: a 10 ms futex wait woken by a FUTEX_WAKE after a 1 ms sleep ends at 1 ms + %d ns" % (what, slack),
              r)


def poll_slack(timeout_ns):
    """The slack a poll timeout ends with: the thread's, or 0.1 % of the
    timeout when that is more (at most 100 ms) (docs/DESIGN.md §2)."""
    return max(SLACK, min(timeout_ns // 1000, 100 * MS))


def test_poll_sets_over_256_fds():
    n = native([prog("poll_many"), "300"]).values()
    check(n.get("ready_fds") == "299:POLLIN" and n.get("woken_fds") == "299:POLLIN",
          "natively, the last pipe is the one reported ready", n)
    v, r = lockstep(prog("poll_many"), "300")
    for key in ("poll_ret", "ppoll_ret", "ready_ret", "ready_fds", "woken_ret", "woken_fds"):
        check(v[key] == n[key], "over 256 fds: %s is %s, as natively" % (key, n[key]), r)
    for call in ("poll", "ppoll"):
        check(int(v["%s_ns" % call]) == 10 * MS + poll_slack(10 * MS),
              "%s of 300 fds, 10 ms timeout: 10 ms + %d ns of virtual time" % (call, poll_slack(10 * MS)), r)
    check(int(v["ready_ns"]) == 0, "a fd ready before the call: poll returns at once", r)
    # Written by the child 5 ms (and its sleep's slack) after the fork, read
    # before the write: the set is looked at again at every step, so the
    # wait ends at the first step boundary at or after the write, no sooner.
    write_at, woken_at = int(v["write_at"]) - EPOCH_MONOTONIC, int(v["woken_at"]) - EPOCH_MONOTONIC
    next_step = -(-write_at // STEP) * STEP
    print("  300 fds: written at %d ns, ppoll woken at %d ns (the step boundary: %d)" % (write_at, woken_at, next_step))
    check(write_at <= woken_at <= next_step,
          "a fd made ready at %d ns ends ppoll by the next step (%d ns), not before: %d ns" %
          (write_at, next_step, woken_at), r)


def test_the_65th_timerfd_fails_with_emfile_said_once():
    n = native([prog("timerfd_limit")]).values()
    check(n.get("created") == "66", "natively, 66 timerfds are made (the limit is tcs's)", n)
    for mode in ("cpu", "lockstep"):
        r = tcs("-m", mode, "--spin-cost", "0", prog("timerfd_limit"), timeout=60) if mode == "lockstep" else \
            tcs("-m", mode, prog("timerfd_limit"), timeout=60)
        v = r.values()
        check(r.returncode == 0 and v.get("created") == "64", "%s: 64 timerfds are made" % mode, r)
        check(v.get("first_refusal") == "EMFILE" and v.get("second_refusal") == "EMFILE",
              "%s: the 65th, and the next, fail with EMFILE" % mode, r)
        check(r.stderr.count("more than 64 timerfds") == 1, "%s: said once, for two refusals" % mode, r)
        check(v.get("after_close") == "ok", "%s: 64 at a time: one closed, one more can be made" % mode, r)
        check(v.get("expirations") == "1", "%s: and it works: one expiration read" % mode, r)
        if mode == "lockstep":
            check(int(v["expiry_ns"]) == 2 * MS, "lockstep: its 2 ms expiry is read at 2 ms exactly (no slack)", r)


if __name__ == "__main__":
    main(globals())
