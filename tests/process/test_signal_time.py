"""A signal sent by a controller acts at the sender's virtual time
(tcs-run(1), Signals; docs/DESIGN.md §3 and §10): a receiver asleep has
its handler run, and its sleep end with EINTR, at the moment the sender
sent it, whether the sender is another process (sigqueue, tgkill) or
another thread of its own (tgkill to a thread, sigqueue to its own
process). Checked exactly in lockstep (--spin-cost 0: clock reads are
free): the sender sends 3 ms and its sleep's timer slack (50 us,
docs/DESIGN.md §2) after the start, the handler's clock reads that, and
the receiver's 1 s sleep has the rest left. What the signal carries, and
how the sleep ends, are as natively (tests/programs/signal_time.c)."""

from harness import SLACK, check, main, native, prog, tcs

MS = 1000000
SEND_AT = 3 * MS + SLACK


def test_a_signal_acts_at_the_senders_time():
    for how in ("sigqueue", "tgkill", "thread_tgkill", "thread_sigqueue"):
        n = native([prog("signal_time"), how]).values()
        r = tcs("-q", "-m", "lockstep", "--spin-cost", "0", prog("signal_time"), how, timeout=60)
        v = r.values()
        check(r.returncode == 0 and v.get("value") == n.get("value") and v.get("sleep_errno") == n.get("sleep_errno")
              == "EINTR", "%s: the handler gets value %s and the sleep ends with EINTR, as natively" %
              (how, n.get("value")), r)
        check(int(v["sent"]) == SEND_AT, "%s: sent 3 ms + 50 us after the start" % how, r)
        check(int(v["handled"]) == SEND_AT, "%s: the receiver's handler reads the sender's time, %d ns: %s" %
              (how, SEND_AT, v["handled"]), r)
        check(int(v["left"]) == 1000 * MS - SEND_AT, "%s: its 1 s sleep had the rest left" % how, r)


if __name__ == "__main__":
    main(globals())
