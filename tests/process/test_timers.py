"""Timers in virtual time (issue 6): timerfd_create / timerfd_settime /
timerfd_gettime, waited on by read, poll, select and epoll, periodic, with
overrun counts and non-blocking reads; and signal timers (setitimer,
alarm, timer_create with SIGEV_SIGNAL and SIGEV_THREAD_ID) pacing legacy
loops that wait with sigsuspend or pause, and interrupting sleeps."""

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


def test_signal_timers_pace_a_legacy_loop():
    for how in ("itimer", "posix", "thread"):
        r = tcs("-q", "-m", "lockstep", prog("alarm_loop"), how, 1000, 1000, 0)
        v = r.values()
        print("  %-6s lockstep: %s ticks in %s ns" % (how, v["ticks"], v["loop_ns"]))
        check(v["ticks"] == "1000" and v["loop_ns"] == "1000000000",
              "%s: 1000 signals of a 1 ms timer take exactly 1 s of virtual time" % how, r)
        check(v["left_ns"] == "1000000", "%s: the timer's time left, in virtual time" % how, r)
        check(v["unslept"] == "4" and v["slept_ns"] == "1000000000",
              "%s: alarm(1) ends sleep(5) after 1 s, 4 s unslept" % how, r)
        # cpu mode, 30 % work: the signal comes on time, the loop keeps its rate.
        r = tcs("-q", prog("alarm_loop"), how, 500, 1000, 300)
        v = r.values()
        print("  %-6s cpu mode, 300 us work: %s ticks in %.3f ms" % (how, v["ticks"], int(v["loop_ns"]) / 1e6))
        check(v["ticks"] == "500", "%s: every tick handled" % how, r)
        # Each tick comes at its expiry, a whole number of periods after the
        # timer was armed; the loop ends just after the 500th handled
        # (ticked_ns: from just before the arming to just after that). A
        # round of work that a pause of the machine made longer than a
        # period (charged as CPU, natively too) may span two expiries, which
        # coalesce: lost ticks, as many as the program's own account of such
        # rounds allows (pause_ticks), no more. Beyond the whole periods
        # only CPU: the arming call's and what follows the last tick, each
        # no more than the kernel charged for it (head and tail_kernel_ns).
        took, paused = int(v["ticked_ns"]), int(v["pause_ticks"])
        cpu = int(v["head_kernel_ns"]) + int(v["tail_kernel_ns"])
        fits = [lost for lost in range(paused + 1) if 0 <= took - (500 + lost) * 1000000 <= cpu]
        check(fits, "%s: %d ns: 500 ticks of 1 ms (or up to %d more, lost to pauses) and at most %d ns of CPU" %
              (how, took, paused, cpu), r)


def test_an_overloaded_signal_loop_runs_late():
    # 1.5 ms of work per 1 ms tick: the timer interrupts the computation
    # (the signal is pending when it is done), ticks coalesce, the loop
    # runs at the pace of its work, as it would on the robot.
    r = tcs("-q", prog("alarm_loop"), "itimer", 200, 1000, 1500)
    v = r.values()
    took, cpu = int(v["loop_ns"]), int(v["loop_cpu_ns"])
    print("  200 ticks with 1.5 ms of work each: %.1f ms, %.1f ms of CPU" % (took / 1e6, cpu / 1e6))
    # Always busy (each tick pending when its work is done), it takes
    # exactly the CPU it used: its work, and the signals' own cost, which
    # is tens of microseconds a tick where system calls cost 1 us.
    check(200 * 1.5e6 <= cpu <= 200 * 1.5e6 * 1.05, "1.5 ms of work a tick, and little else", r)
    close_to(took, cpu, 0.005, "the loop takes its CPU's time", r)


def test_alarm_and_pause():
    r = tcs("-q", prog("alarm_loop"), "alarm", 3, 0, 0)
    v = r.values()
    check(v["ticks"] == "3", "three alarms", r)
    close_to(int(v["loop_ns"]), 3e9, 0.0001, "alarm(1) and pause() three times: 3 s of virtual time", r)


def test_sigev_thread_timers_call_their_function_in_virtual_time():
    # Lockstep: every call exactly on its expiry, on a thread of its own.
    r = tcs("-q", "-m", "lockstep", prog("notify_timer"), 1000, 1000)
    v = r.values()
    print("  lockstep: %s calls, first at %s ns, last at %s ns" % (v["calls"], v["first_ns"], v["last_ns"]))
    check(v["calls"] == "1000" and v["expiries"] == "1000", "1000 calls, one per expiry", r)
    check(v["first_ns"] == "1000000" and v["last_ns"] == "1000000000" and v["max_late_ns"] == "0",
          "each call at its expiry exactly: the first at 1 ms, the last at 1 s", r)
    check(v["after_delete"] == "0", "no call after timer_delete", r)
    check(v["other_thread"] == "1", "the function runs on another thread, with its sigev_value", r)
    # cpu mode, light function: on time within the noise of one core.
    r = tcs("-q", prog("notify_timer"), 500, 1000, 100)
    v = r.values()
    print("  cpu mode, 100 us each: %s calls for %s expiries, at most %s ns late" %
          (v["calls"], v["expiries"], v["max_late_ns"]))
    # (A call held up past the next expiry folds it in as an overrun.)
    check(490 <= int(v["calls"]) <= 500 and v["after_delete"] == "0", "500 calls or about, none after timer_delete", r)
    check(int(v["expiries"]) - int(v["last_ns"]) // 1000000 in (0, 1), "the expiries are the periods that passed", r)
    check(int(v["max_late_ns"]) < 1000000, "no call a period late", r)
    # cpu mode, a function that takes 2.5 periods: the expiries that pass
    # while it runs are its successor's overrun. Over 100 periods: 40 calls.
    r = tcs("-q", prog("notify_timer"), 100, 1000, 2500)
    v = r.values()
    print("  cpu mode, 2.5 ms each: %s calls for %s expiries over %.1f ms" %
          (v["calls"], v["expiries"], int(v["last_ns"]) / 1e6))
    check(38 <= int(v["calls"]) <= 41 and v["after_delete"] == "0", "a call per 2.5 ms, none after timer_delete", r)
    check(abs(int(v["expiries"]) - int(v["last_ns"]) // 1000000) <= 1, "overruns count every period that passed", r)


if __name__ == "__main__":
    main(globals())
