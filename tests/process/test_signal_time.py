"""A signal sent by a controller acts at the sender's virtual time
(tcs-run(1), Signals; docs/DESIGN.md §3 and §10): a receiver asleep has
its handler run, and its sleep end with EINTR, at the moment the sender
sent it, whether the sender is another process (sigqueue, tgkill) or
another thread of its own (tgkill to a thread, sigqueue to its own
process). Checked exactly in lockstep (--spin-cost 0: clock reads are
free): the sender sends 3 ms and its sleep's timer slack (50 us,
docs/DESIGN.md §2) after the start, the receiver's 1 s sleep has the rest
left, and its handler's clock reads the sending time ("a signal handler
runs at the virtual time the signal was delivered", shared/DESIGN.md §10).
What the signal carries, and how the sleep ends, are as natively
(tests/programs/signal_time.c)."""

from harness import SLACK, check, main, native, prog, tcs

MS = 1000000
SEND_AT = 3 * MS + SLACK
HOWS = ("sigqueue", "tgkill", "thread_tgkill", "thread_sigqueue")
# Runs of each way: the handler's clock (below) read wrong in a race,
# about 1 run in 2 of the cross-process ones on this machine, before it
# was fixed; 40 make a return of it all but certain to show.
RUNS = 40
_runs = {}


def sent(how):
    """The runs of signal_time HOW in lockstep (made once, shared by the
    tests), each checked for what the signal carries and when it was sent:
    the native run's values and theirs."""
    if how in _runs:
        return _runs[how]
    n = native([prog("signal_time"), how]).values()
    runs = []
    for _ in range(RUNS):
        r = tcs("-q", "-m", "lockstep", "--spin-cost", "0", prog("signal_time"), how, timeout=60)
        v = r.values()
        check(r.returncode == 0 and v.get("value") == n.get("value"), "%s: the handler gets value %s, as natively" %
              (how, n.get("value")), r)
        check(int(v["sent"]) == SEND_AT, "%s: sent 3 ms + 50 us after the start" % how, r)
        runs.append((v, r))
    _runs[how] = n, runs
    return n, runs


def test_a_signal_ends_a_wait_at_the_senders_time():
    # sigqueue and tgkill from another process that sleeps on after its
    # send (signal_time does): the receiver's 1 s sleep ends with EINTR at
    # the send, as natively. (Found by this test: the handler ran but the
    # sleep went on to its end, every run. Told of the signal, the
    # coordinator wakes the receiver to re-check at the sender's time,
    # before the kernel has sent it; the receiver waited again through its
    # mailbox, where a handler counts as one just before the wait. Now the
    # re-check's answer holds signals blocked, and the next wait lets them
    # in where it notices them: docs/DESIGN.md §10.)
    wrong = []
    for how in HOWS:
        n, runs = sent(how)
        check(n.get("sleep_errno") == "EINTR", "%s: natively the sleep ends with EINTR" % how, n)
        ends = sorted(set("%s %s %s" % (v["sleep_errno"], v["woke"], v["left"]) for v, _ in runs))
        print("  %-16s sleep ended (errno, at, left): %s" % (how, "; ".join(ends)))
        wrong += ["%s: %s" % (how, e) for e in ends if e != "EINTR %d %d" % (SEND_AT, 1000 * MS - SEND_AT)]
    check(not wrong, "each 1 s sleep ends with EINTR at the sender's %d ns with the rest left, not: %s" %
          (SEND_AT, "; ".join(wrong)))


def test_a_handler_reads_the_senders_time():
    # sigqueue and tgkill from another process: the handler's clock reads
    # the sender's time. (Found by this test, about 1 run in 2: it read the
    # receiver's time before its wait, the handler having run in the
    # mailbox's spin before the re-check's wake was read; fixed with the
    # above.) Between threads of one process the page is the sender's.
    wrong = []
    for how in HOWS:
        _, runs = sent(how)
        read = sorted(set(v["handled"] for v, _ in runs))
        print("  %-16s sent at %d ns, handler read %s ns" % (how, SEND_AT, ", ".join(read)))
        wrong += ["%s: %s ns" % (how, t) for t in read if int(t) != SEND_AT]
    check(not wrong, "the receiver's handler reads the sender's time, %d ns, not: %s" % (SEND_AT, "; ".join(wrong)))


if __name__ == "__main__":
    main(globals())
