"""Timers in virtual time (issue 6): timerfd_create / timerfd_settime /
timerfd_gettime, waited on by read, poll, select and epoll, periodic, with
overrun counts and non-blocking reads."""

from harness import check, close_to, main, prog, tcs


def test_timerfd_paces_a_loop_exactly_in_lockstep():
    for how in ("read", "poll", "select", "epoll"):
        r = tcs("-q", "-m", "lockstep", prog("timer_loop"), how, 1000, 1000)
        v = r.values()
        print("  %-6s %s expirations in %s ns" % (how, v["expirations"], v["loop_ns"]))
        check(v["bad"] == "0", "%s: every wait ended with the timer readable" % how, r)
        check(v["expirations"] == "1000", "%s: one expiration per period" % how, r)
        check(v["loop_ns"] == "1000000000", "%s: 1000 periods of 1 ms take exactly 1 s of virtual time" % how, r)
        check(v["first_left_ns"] == "1000000" and v["interval_ns"] == "1000000",
              "%s: timerfd_gettime in virtual time" % how, r)
        check(v["eagain"] == "1", "%s: a non-blocking read before the expiry is EAGAIN" % how, r)


def test_overruns_are_counted_in_cpu_mode():
    # 2.5 ms of the loop's own CPU per 1 ms period: each read returns the
    # expirations it missed, and they add up to the time the loop took.
    for how in ("read", "epoll"):
        r = tcs("-q", prog("timer_loop"), how, 200, 1000, 2500)
        v = r.values()
        took, n = int(v["loop_ns"]), int(v["expirations"])
        print("  %-6s %d expirations in %.1f ms" % (how, n, took / 1e6))
        check(v["bad"] == "0", "%s: reads succeed" % how, r)
        close_to(took, 200 * 2.5e6, 0.02, "%s: the loop takes its work's time" % how, r)
        # Counted up to the last read, before the last round of work.
        check(abs(n - (took - 2500000) // 1000000) <= 1, "%s: every period that passed is counted once" % how, r)


if __name__ == "__main__":
    main(globals())
