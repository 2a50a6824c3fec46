/* Spins in lockstep (spin.h). What spinning adds to virtual time is the
 * clock page's spin_v, stored by the spinning thread itself, up to the
 * coordinator's spin_limit (the world's next step, the controller's next
 * timer, another of its threads' wake). There it asks with a wait of its
 * own (TCS_BLOCK_SPIN) that ends at the time it reached, once the world and
 * the others are there, and goes on. */
#include "spin.h"

#include "raw_syscall.h"
#include "wait.h"

int64_t tcs_spin_to(int64_t v, int held)
{
	struct tcs_clock_page *p = tcs_rt.page;
	if (v < __atomic_load_n(&p->spin_limit, __ATOMIC_ACQUIRE)) {
		/* Another thread may have spun further meanwhile: the larger. */
		int64_t old = __atomic_load_n(&p->spin_v, __ATOMIC_RELAXED);
		while (old < v && !__atomic_compare_exchange_n(&p->spin_v, &old, v, 1, __ATOMIC_RELEASE,
								 __ATOMIC_RELAXED))
			;
		return old < v ? v : old;
	}
	if (!held && !tcs_wait_enter())
		return tcs_vnow(); /* no channel: it cannot ask, so it stays */
	struct tcs_wait_time t = { v, 0, 0, 0, 0, 0 };
	(void)tcs_wait(&t, TCS_BLOCK_SPIN, 0, NULL, 0, NULL);
	if (!held)
		tcs_wait_leave();
	/* Threads it woke (their waits ended here too) share its core at its
	 * priority: they run first, as the kernel's wake-up preemption would
	 * let them natively, or a spin for what they do would outlast them. */
	tcs_sys0(SYS_sched_yield);
	tcs_spun = 1; /* (the wait was the spin's, not the program's) */
	return tcs_vnow();
}

/* Virtual time after a call that costs cost ns when it spins. held: the
 * caller is inside a hook's wait already. */
static int64_t tcs_spin_advance(int64_t cost, int held)
{
	int64_t now = tcs_vnow();
	if (!tcs_spun || cost <= 0) {
		tcs_spun = 1;
		return now;
	}
	return tcs_spin_to(tcs_ns_add(now, cost), held);
}

int64_t tcs_spin_clock_read(void)
{
	/* (A signal handler's reads inside a hook spin too: its wait, if it
	 * must, ends the hook's first, roundtrip.c.) */
	return tcs_spin_advance(tcs_rt.page->spin_clock_ns, 0);
}

void tcs_spin_empty_read(int held)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	if (p->mode != TCS_MODE_LOCKSTEP || (p->flags & TCS_PAGE_REPLAY))
		return; /* (replaying: what it cost is in the record) */
	(void)tcs_spin_advance(p->spin_read_ns, held);
}
