/* Spins in lockstep (spin.h). What spinning adds to virtual time is the
 * clock page's spin_v, stored by the spinning thread itself, up to the
 * coordinator's spin_limit (the world's next step, the controller's next
 * timer, another of its threads' wake). There it asks with a wait of its
 * own (TCS_BLOCK_SPIN) that ends at the time it reached, once the world and
 * the others are there, and goes on. */
#include "spin.h"

#include <poll.h>

#include "cpu_estimate.h"
#include "raw_syscall.h"
#include "thread_channels.h"
#include "wait.h"

/* (More threads than this: the rest are not waited for.) */
#define TCS_MAX_YIELD_CHANNELS 64

/* Threads its wait's end woke (their waits ended at its time too) share
 * its core at its priority: they run first, as the kernel's wake-up
 * preemption would let them natively, or a spin for what they do would
 * outlast them. The coordinator answers them before this thread, but a
 * wake-up reaches this core later than the answer is written: so it
 * yields while another thread's answer is still unread, up to 1 ms of real
 * time (a thread that is not ours to wait for: stopped, or gone). */
static void tcs_yield_to_woken(void)
{
	const int mine = tcs_my_channel();
	struct pollfd fds[TCS_MAX_YIELD_CHANNELS];
	int n = 0;
	if (__atomic_load_n(&tcs_rt.page->threads_started, __ATOMIC_RELAXED) != 0) {
		int channels[TCS_MAX_YIELD_CHANNELS];
		int k = tcs_thread_channels(channels, TCS_MAX_YIELD_CHANNELS - 1);
		for (int i = 0; i < k; i++)
			if (channels[i] != mine)
				fds[n++] = (struct pollfd){ channels[i], POLLIN, 0 };
		if (mine != tcs_rt.channel_fd)
			fds[n++] = (struct pollfd){ tcs_rt.channel_fd, POLLIN, 0 };
	}
	const int64_t until = tcs_kernel_clock(CLOCK_MONOTONIC) + TCS_NS_PER_MS;
	for (;;) {
		tcs_sys0(SYS_sched_yield);
		if (n == 0)
			return;
		struct timespec zero = { 0, 0 };
		int main_unread = mine != tcs_rt.channel_fd &&
				  (__atomic_load_n(&tcs_rt.page->mailbox.state, __ATOMIC_ACQUIRE) & TCS_MBOX_ANSWER);
		if ((tcs_sys5(SYS_ppoll, fds, n, &zero, NULL, 0) <= 0 && !main_unread) ||
		    tcs_kernel_clock(CLOCK_MONOTONIC) >= until)
			return;
	}
}

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
	tcs_yield_to_woken();
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
