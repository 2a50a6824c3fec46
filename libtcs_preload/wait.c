/* Waiting in virtual time (wait.h): a BLOCK with its deadline and the CPU
 * up to the hook's entry, answered by a WAKE at the time the wait ended
 * (roundtrip.c carries both). Blocking hooks are built on tcs_wait between
 * tcs_wait_enter and tcs_wait_leave.
 *
 * Hooks nest: a signal handler that runs inside one (its wait, or the
 * timer signals it raises) enters its own, whose request settles the
 * interrupted one first (roundtrip.c). */
#include "journal_write.h"
#include "raw_syscall.h"
#include "roundtrip.h"
#include "signal_mask.h"
#include "signal_timers.h"
#include "vclock.h"
#include "wait.h"

static void tcs_send_kill(long target)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_KILL, 0), w;
	m.arg = target;
	m.cpu = tcs_charge_point(TCS_MSG_KILL);
	m.v = tcs_vnow();
	tcs_roundtrip(&m, NULL, 0, NULL, &w, NULL);
}

void tcs_signal_sending(long target, int sig)
{
	if (sig == 0 || target == tcs_rt.pid || !tcs_wait_enter())
		return;
	tcs_send_kill(target);
	tcs_wait_leave();
}

void tcs_signal_sent(long target, long tid, int sig)
{
	if (sig == 0 || (target != tcs_rt.pid && target != 0 && target != -1) || !tcs_active() ||
	    __atomic_load_n(&tcs_rt.page->threads_started, __ATOMIC_RELAXED) == 0)
		return;
	if (tid != 0 && tid == tcs_sys0(SYS_gettid))
		return;
	if (!tcs_wait_enter())
		return;
	tcs_send_kill(tcs_rt.pid);
	tcs_wait_leave();
}

/* Timer signals due during a wait: raised here, inside the wait, so that
 * they meet the wait's signal mask; then the kernel says whether a handler
 * ran (EINTR) or not (ignored, or blocked: wait on). */
static int tcs_raise_timer_signals(uint64_t bits, const sigset_t *mask)
{
	/* Blocked while raised (a signal sent to oneself is delivered on the
	 * way out of kill), then let in by the wait's mask in a ppoll that
	 * does not wait. Every signal is blocked, not just these: a handler
	 * run in the ppoll returns to the mask the ppoll began with, and
	 * another signal that became due meanwhile (raised by that handler,
	 * blocked in it) is delivered there at once, its handler running
	 * with that mask. With these alone blocked, a SIGALRM handler run
	 * after a SIGUSR1 one had SIGUSR1 blocked, as natively it never has,
	 * and waited in vain for the next (the idiom corpus's
	 * nested/timer usleep select). With all blocked, it runs as the
	 * mask is given back, with the wait's. */
	uint64_t old = tcs_signals_block();
	long pid = tcs_sys0(SYS_getpid);
	for (int sig = 1; sig <= 64; sig++) {
		if (!(bits & (1ull << (sig - 1))))
			continue;
		int tid = tcs_timer_signal_target(sig);
		if (tid > 0)
			tcs_sys3(SYS_tgkill, pid, tid, sig);
		else
			tcs_sys2(SYS_kill, pid, sig);
	}
	struct timespec zero = { 0, 0 };
	long r = tcs_sys5(SYS_ppoll, NULL, 0, &zero, mask ? (const void *)mask : (const void *)&old,
			  TCS_KERNEL_SIGSET_SIZE);
	tcs_signals_restore(old);
	return r == -EINTR ? -EINTR : TCS_WAIT_RECHECK;
}

/* Awake after the coordinator stepped us aside (TCS_PAGE_ASLEEP): a wait
 * already due, which the coordinator answers at the world's time
 * (TCS_BLOCK_ASK). It was a wait of 1 ns: when the coordinator had seen us
 * wake just before (a new slice, the flag not yet cleared), it ended 1 ns
 * after the world's time, and a lockstep run was 1 ns long (1 in 40 runs
 * under load). */
static __thread int tcs_catching_up;

static void tcs_catch_up_in_wait(void)
{
	if (tcs_catching_up)
		return;
	tcs_catching_up = 1;
	tcs_replay_inner_begin(); /* (what the world's time is, the record says) */
	struct tcs_wait_time t = { 0, 1, 0, 0, 0, 0 };
	(void)tcs_wait(&t, TCS_BLOCK_SLEEP, TCS_BLOCK_ASK, NULL, 0, NULL);
	tcs_replay_inner_end();
	tcs_catching_up = 0;
}

void tcs_catch_up(void)
{
	if (!tcs_wait_enter())
		return;
	tcs_catch_up_in_wait();
	tcs_wait_leave();
}

static int tcs_wait_in(struct tcs_wait_time *t, unsigned kind, unsigned flags, struct pollfd *fds, unsigned nfds,
		       const sigset_t *mask, struct tcs_wait_hold *hold);

int tcs_wait(struct tcs_wait_time *t, unsigned kind, unsigned flags, struct pollfd *fds, unsigned nfds,
	     const sigset_t *mask)
{
	return tcs_wait_in(t, kind, flags, fds, nfds, mask, NULL);
}

long tcs_wait_held(struct tcs_wait_time *t, struct tcs_wait_hold *h, unsigned kind, unsigned flags)
{
	return tcs_wait_in(t, kind, flags, NULL, 0, h->holding ? (const sigset_t *)(const void *)&h->mask : NULL, h);
}

void tcs_wait_unhold(struct tcs_wait_hold *h)
{
	if (h->holding)
		tcs_signals_restore(h->mask);
	h->holding = 0;
}

static int tcs_wait_in(struct tcs_wait_time *t, unsigned kind, unsigned flags, struct pollfd *fds, unsigned nfds,
		       const sigset_t *mask, struct tcs_wait_hold *hold)
{
	struct tcs_clock_page *p = tcs_rt.page;
	if (__builtin_expect(__atomic_load_n(&p->flags, __ATOMIC_RELAXED) & TCS_PAGE_ASLEEP, 0))
		tcs_catch_up_in_wait();
	/* The charge up to here, and virtual time from it in cpu mode. */
	int64_t cpu = tcs_charge_point(TCS_MSG_BLOCK);
	int64_t v = tcs_page_vnow(p, tcs_page_read_slice(p), cpu);
	/* A relative wait counts from the latest time the program was told,
	 * so it never sees a sleep end before it should have. */
	int64_t deadline = t->relative ? tcs_ns_add(tcs_v_not_before(v), t->deadline) : t->deadline;
	t->deadline = deadline;
	t->relative = 0;
	t->start = v;
	int report = (flags & TCS_BLOCK_ABSOLUTE) && (p->flags & TCS_PAGE_REPORT_MISSES);
	if (deadline <= v && !report && !(flags & TCS_BLOCK_ASK)) {
		__atomic_add_fetch(&p->quick_returns, 1, __ATOMIC_RELAXED);
		if (flags & TCS_BLOCK_ABSOLUTE)
			__atomic_add_fetch(&p->past_deadlines, 1, __ATOMIC_RELAXED);
		t->end = v;
		if (__builtin_expect(tcs_journal_on(), 0))
			tcs_journal_answered(TCS_MSG_BLOCK, v);
		return TCS_WAIT_DEADLINE;
	}

	/* A wait with its own signal mask (sigsuspend, ppoll, pselect,
	 * epoll_pwait) may let in a signal already pending: then it ends now,
	 * before the coordinator could decide anything else. */
	uint64_t raised = 0;
	if (mask) {
		/* What tcs had raised before the look (TCS_BLOCK_SIGMASK): one it
		 * raises after, stopping us between the look and the BLOCK, is
		 * pending unseen, and the coordinator has us look again. */
		raised = __atomic_load_n(&p->signals_raised, __ATOMIC_ACQUIRE);
		struct timespec zero = { 0, 0 };
		if (tcs_sys5(SYS_ppoll, NULL, 0, &zero, mask, TCS_KERNEL_SIGSET_SIZE) == -EINTR) {
			t->end = v;
			return -EINTR;
		}
		flags |= TCS_BLOCK_SIGMASK;
	}

	struct tcs_msg m = tcs_msg_make(TCS_MSG_BLOCK, t->seq);
	m.kind = (uint16_t)kind;
	m.flags = (uint16_t)flags;
	m.arg = (int64_t)raised;
	m.deadline = deadline;
	m.slack = t->slack > 0 ? t->slack : 0;
	m.v = v;
	m.cpu = cpu;
	struct tcs_msg w;
	if (hold && !hold->holding)
		tcs_roundtrip_hold_on_recheck(&m, &hold->mask, &hold->holding);
	unsigned early = tcs_roundtrip(&m, fds, nfds, mask, &w, NULL);
	t->end = w.v;
	tcs_spin_waited();
	/* A handler ran (a timer's signal, say): the wait was interrupted,
	 * whatever the answer that crossed the EARLY says; but timer signals
	 * that answer carries are due all the same and raised (coreutils
	 * timeout's SIGALRM was lost so when a SIGCHLD, for its child stopped
	 * by the coordinator, ended its sigsuspend at that moment). */
	if (early == TCS_EARLY_SIGNAL) {
		if (w.kind == TCS_WAKE_SIGNAL)
			(void)tcs_raise_timer_signals((uint64_t)w.arg, mask);
		return -EINTR;
	}
	if (w.kind == TCS_WAKE_SIGNAL)
		return tcs_raise_timer_signals((uint64_t)w.arg, mask);
	if (w.kind == TCS_WAKE_RECHECK)
		return TCS_WAIT_RECHECK;
	if (w.kind == TCS_WAKE_EARLY)
		return TCS_WAIT_FD;
	return TCS_WAIT_DEADLINE;
}
