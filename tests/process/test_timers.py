"""Timers in virtual time (issue 6): timerfd_create / timerfd_settime /
timerfd_gettime, waited on by read, poll, select and epoll, periodic, with
overrun counts and non-blocking reads; and signal timers (setitimer,
alarm, timer_create with SIGEV_SIGNAL and SIGEV_THREAD_ID) pacing legacy
loops that wait with sigsuspend or pause, and interrupting sleeps."""

from harness import AHEAD, READ, check, main, prog, stop_cost, tcs

MS = 1000000
# notify_timer.c's LOOK_SLACK_NS: its helper looks at the clock (deciding a
# call's overrun) up to a clock read's cost before the call reads its own,
# and an estimated read may run ahead.
LOOK_SLACK = READ + AHEAD


def test_timerfd_paces_a_loop_exactly_in_lockstep():
    for how in ("read", "poll", "select", "epoll"):
        r = tcs("-q", "-m", "lockstep", "--spin-cost", "0", prog("timer_loop"), how, 1000, 1000)
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
        first, busy = int(v["first_ns"]), took - int(v["first_ns"])
        inner, outer = int(v["busy_inner_cpu_ns"]), int(v["busy_cpu_ns"])
        print("  %-6s %d expirations in %.3f ms: the first read at %.3f ms, then %.3f ms for %.3f ms of CPU" %
              (how, n, took / MS, first / MS, busy / MS, outer / MS))
        check(v["bad"] == "0", "%s: reads succeed" % how, r)
        # The first read waits for the first expiry, 1 ms after the arming;
        # beyond it only CPU: the arming's, and what follows the wait (at
        # most the CPU from just before the start to just after that read,
        # and an estimated read ahead).
        check(MS <= first <= MS + int(v["first_cpu_ns"]) + AHEAD,
              "%s: the first read returns 1 ms after the arming, and at most its CPU later: %d ns" % (how, first), r)
        # Then the loop never waits (each read finds the timer expired: its
        # work is longer than the period), so its time is its CPU: no less
        # than its work, 200 rounds of 2.5 ms of the program's own CPU by
        # the kernel's clock (all of it the program's, so all charged), no
        # more than the kernel's CPU read just outside the span (tcs charges
        # no more than the kernel did; either monotonic read estimated,
        # ahead or as far behind). Both bounds are the kernel's figures: a
        # tcs that overcharged would also inflate the CPU clock it answers.
        check(200 * 2500000 - 2 * AHEAD <= busy <= outer + 2 * AHEAD,
              "%s: the busy loop takes its CPU's time: %d ns for its 200 x 2.5 ms of work, at most the kernel's "
              "%d ns (inside: %d ns)" % (how, busy, outer, inner), r)
        # Every period that passed is counted once: the expirations are the
        # whole periods from the arming (between the start and armed_ns) to
        # the last read's look at the clock (between last_read_from_ns and
        # last_read_to_ns).
        lo = (int(v["last_read_from_ns"]) - int(v["armed_ns"])) // MS
        hi = int(v["last_read_to_ns"]) // MS
        check(lo <= n <= hi, "%s: %d expirations, the periods that passed: %d to %d" % (how, n, lo, hi), r)


def test_signal_timers_pace_a_legacy_loop():
    for how in ("itimer", "posix", "thread"):
        r = tcs("-q", "-m", "lockstep", "--spin-cost", "0", prog("alarm_loop"), how, 1000, 1000, 0)
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
    # runs at the pace of its work, as it would on the robot. Again with
    # every stop 600 us late, as on a busy machine (TCS_STOP_DELAY_US): the
    # round's work often ends before its expiry's stop lands, and its
    # sigsuspend has looked for a pending signal before tcs sends it; it
    # must still end at once (it would wait for the next expiry otherwise:
    # 86 ms beyond its CPU).
    for late in (None, "600"):
        overloaded_signal_loop({"TCS_STOP_DELAY_US": late} if late else None)


def overloaded_signal_loop(env):
    r = tcs("-q", prog("alarm_loop"), "itimer", 200, 1000, 1500, env=env)
    v = r.values()
    took, cpu = int(v["loop_ns"]), int(v["loop_cpu_ns"])
    print("  200 ticks with 1.5 ms of work each%s: %.3f ms, %.3f ms of CPU" %
          (", stops 600 us late" if env else "", took / MS, cpu / MS))
    # Its work is by the kernel's clock: charged, less what its stops cost
    # it (the kernel's clock counts them; tcs leaves them out), each a
    # voluntary switch as each of its sigsuspends is: no more than the
    # machine's cost of a stop for each (stop_cost()); and tcs charges no
    # more than the kernel did around the loop (either side: what a read
    # runs ahead).
    kernel, stops = int(v["loop_kernel_cpu_ns"]), int(v["loop_switches"]) * stop_cost()
    check(200 * 1.5 * MS - stops - AHEAD <= cpu <= kernel + AHEAD,
          "1.5 ms of work a tick: %d ns charged, the kernel's %d ns, its stops' at most %d" % (cpu, kernel, stops), r)
    # Always busy (each tick pending when its work is done), it takes
    # exactly the CPU it was charged: its work, less the stops as above, and
    # no more than the kernel's CPU around it (each of the two clock reads
    # estimated, 20 us either way). The kernel's figures, not the CPU clock
    # tcs answers, which an overcharge would inflate with the time.
    check(200 * 1.5 * MS - stops - 2 * AHEAD <= took <= kernel + 2 * AHEAD,
          "the loop takes its CPU's time: %d ns for 200 x 1.5 ms of work, the kernel's %d ns" % (took, kernel), r)


def test_alarm_and_pause():
    r = tcs("-q", prog("alarm_loop"), "alarm", 3, 0, 0)
    v = r.values()
    took, cpu = int(v["loop_ns"]), int(v["loop_kernel_cpu_ns"])
    print("  alarm(1) and pause() three times: %d ns, %d ns of CPU" % (took, cpu))
    check(v["ticks"] == "3", "three alarms", r)
    # Each pause() ends 1 s after its alarm(1), which comes after the
    # previous pause's end by the loop's CPU (by the kernel's clock, read
    # around loop_ns's span: tcs charges no more; the last monotonic read
    # estimated).
    check(3000 * MS <= took <= 3000 * MS + cpu + AHEAD,
          "alarm(1) and pause() three times: 3 s of virtual time and at most the loop's CPU: %d ns" % took, r)


def test_sigev_thread_timers_call_their_function_in_virtual_time():
    # Lockstep: every call exactly on its expiry, on a thread of its own.
    r = tcs("-q", "-m", "lockstep", "--no-slack", prog("notify_timer"), 1000, 1000)
    v = r.values()
    print("  lockstep: %s calls, first at %s ns, last at %s ns" % (v["calls"], v["first_ns"], v["last_ns"]))
    check(v["calls"] == "1000" and v["expiries"] == "1000", "1000 calls, one per expiry", r)
    check(v["first_ns"] == "1000000" and v["last_ns"] == "1000000000" and v["max_late_ns"] == "0",
          "each call at its expiry exactly: the first at 1 ms, the last at 1 s", r)
    check(v["after_delete"] == "0", "no call after timer_delete", r)
    check(v["other_thread"] == "1", "the function runs on another thread, with its sigev_value", r)
    # cpu mode, light function: on time within the noise of one core.
    r = tcs("-q", "--no-slack", prog("notify_timer"), 500, 1000, 100)
    v = r.values()
    calls, expiries = int(v["calls"]), int(v["expiries"])
    print("  cpu mode, 100 us each: %d calls for %d expiries, at most %s ns late; %s overruns a pause explains" %
          (calls, expiries, v["max_late_ns"], v["pause_overruns"]))
    check(v["after_delete"] == "0", "none after timer_delete", r)
    # A call held up past the next expiry folds it in as an overrun: only
    # a round (one call's start to the next's) longer than a period by the
    # kernel's CPU does that, which for 100 us of work is a pause of the
    # machine (pause_overruns: notify_timer.c). An expiry after the last
    # call goes without one only if the helper had not reached it when main
    # woke, half a period after the 500th at least: the CPU since the last
    # call (tail_kernel_ns, with the helper's look at the clock up to
    # LOOK_SLACK from it) holds as many as (tail + slack) / period + 1/2.
    end = (int(v["tail_kernel_ns"]) + LOOK_SLACK + MS // 2) // MS
    check(500 - calls <= int(v["pause_overruns"]) + end,
          "500 calls, less no more than the expiries pauses explain (%s, and %d at the end)" % (v["pause_overruns"], end), r)
    # Each call stands for an expiry, the k-th k periods after the arming
    # at the earliest: no more calls than periods before the deletion.
    check(calls <= int(v["deleted_ns"]) // MS, "no more calls than periods before timer_delete", r)
    expiries_are_the_periods_that_passed(v, r)
    # No call a period late: each stands for the latest expiry by the
    # helper's look at the clock, less than a period before it, counted
    # from the arming (up to armed_ns after the start max_late_ns counts
    # from), the look up to LOOK_SLACK before the call's reading.
    check(int(v["max_late_ns"]) < MS + int(v["armed_ns"]) + LOOK_SLACK,
          "no call a period late: %s ns" % v["max_late_ns"], r)
    # cpu mode, a function that takes 2.5 periods: the expiries that pass
    # while it runs are its successor's overrun.
    r = tcs("-q", prog("notify_timer"), 100, 1000, 2500)
    v = r.values()
    calls, first, last = int(v["calls"]), int(v["first_ns"]), int(v["last_ns"])
    print("  cpu mode, 2.5 ms each: %d calls for %s expiries from %.3f to %.3f ms (main woke at %.3f ms)" %
          (calls, v["expiries"], first / MS, last / MS, int(v["woke_ns"]) / MS))
    check(v["after_delete"] == "0", "none after timer_delete", r)
    # The helper is always behind: each call starts as the one before ends,
    # so the calls come one round of the process's CPU apart (virtual time
    # passes by it alone, and tcs charges no more than the kernel does:
    # calls_kernel_ns, read around the first and the last call's clock
    # reads), each round at least the function's 2.5 ms, less what the
    # stops tcs made of its work cost (the kernel counts that as the
    # work's CPU; tcs leaves it out), until main deletes the timer (how
    # long after 100.5 ms main gets the core is the kernel's choice
    # between two threads on one core: 40 calls, or 41).
    stops = int(v["work_stops_before_last"])
    check((calls - 1) * 2500000 - stops * stop_cost() <= last - first + AHEAD,
          "%d calls, each at least 2.5 ms after the one before (%d stops)" % (calls, stops), r)
    check(last - first <= int(v["calls_kernel_ns"]) + AHEAD,
          "the calls come back to back: %d ns from the first to the last, %s ns of CPU" %
          (last - first, v["calls_kernel_ns"]), r)
    check(last <= int(v["deleted_ns"]) and int(v["woke_ns"]) - last <= int(v["tail_kernel_ns"]) + AHEAD,
          "the last call before timer_delete, and main woke while it ran", r)
    expiries_are_the_periods_that_passed(v, r)


def expiries_are_the_periods_that_passed(v, r):
    """notify_timer's expiries: each call stands for the expiries up to the
    helper's look at the clock, whole periods from the arming (between
    notify_timer's start and armed_ns); that look comes before the call's
    own reading (last_ns), by no more than LOOK_SLACK."""
    last, n = int(v["last_ns"]), int(v["expiries"])
    lo, hi = (last - LOOK_SLACK - int(v["armed_ns"])) // MS, last // MS
    check(lo <= n <= hi, "%d expiries, the periods that passed by the last call at %d ns: %d to %d" %
          (n, last, lo, hi), r)


if __name__ == "__main__":
    main(globals())
