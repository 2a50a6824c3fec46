/* The controller's side of the mailbox (tcs/mailbox.h): a request handed
 * to the coordinator through the clock page and its answer awaited by
 * spinning on this core, which is the controller's alone while the
 * coordinator polls on its own. The round trip (roundtrip.c) comes here first
 * and takes the channel when this says no.
 *
 * A signal handler that runs during the spin and calls no hook does not end
 * the wait as one during ppoll would (nothing tells): the spin lasts only
 * until the coordinator answers or parks the request, a few microseconds,
 * and such a handler is as if the signal had come just before the wait
 * began, which a real program meets too. Waits where that would matter
 * take the channel: those with a signal mask of their own, with real fds,
 * or without a deadline (pause, and waits for a handler). A handler that
 * makes a request parks the interrupted one and ends it (roundtrip.c).
 *
 * With other controllers queued behind it on its core (TCS_PAGE_QUEUED,
 * lockstep), it parks at once: its answer comes only once they have run. */
#include "mailbox_post.h"
#include "real.h"

int tcs_mailbox_fits(const struct tcs_msg *m, int channel)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	if (!(__atomic_load_n(&p->flags, __ATOMIC_RELAXED) & TCS_PAGE_MAILBOX) || channel != tcs_rt.channel_fd ||
	    __atomic_load_n(&p->threads_started, __ATOMIC_RELAXED) != 0)
		return 0;
	return tcs_mailbox_carries(m->type) && !(m->type == TCS_MSG_BLOCK && m->deadline == TCS_NEVER);
}

int tcs_mailbox_post(const struct tcs_msg *m)
{
	struct tcs_mailbox *b = &tcs_rt.page->mailbox;
	__builtin_memcpy(&b->request, m, sizeof *m);
	/* Sequentially consistent, both: the store is seen before `polling` is
	 * read, as the coordinator's clearing of `polling` is seen before it
	 * looks at `state` once more (tcs/mailbox.h). */
	__atomic_store_n(&b->state, TCS_MBOX_REQUEST | TCS_MBOX_BUSY, __ATOMIC_SEQ_CST);
	return __atomic_load_n(&b->polling, __ATOMIC_SEQ_CST) == 0;
}

static int64_t tcs_mailbox_clock(void)
{
	struct timespec ts;
	tcs_real_fns.clock_gettime(CLOCK_MONOTONIC, &ts);
	return tcs_ts_to_ns(&ts);
}

void tcs_mailbox_take(struct tcs_msg *reply)
{
	__builtin_memcpy(reply, &tcs_rt.page->mailbox.answer, sizeof *reply);
}

uint32_t tcs_mailbox_park_now(void)
{
	return __atomic_fetch_or(&tcs_rt.page->mailbox.state, TCS_MBOX_PARK, __ATOMIC_ACQ_REL);
}

void tcs_mailbox_unpark(void)
{
	__atomic_fetch_and(&tcs_rt.page->mailbox.state, ~TCS_MBOX_PARK, __ATOMIC_ACQ_REL);
}

int tcs_mailbox_wait(const volatile uint8_t *settled)
{
	struct tcs_mailbox *b = &tcs_rt.page->mailbox;
	int64_t until = 0;
	/* Others queued behind us: no spin, the core is theirs meanwhile. */
	if (__atomic_load_n(&tcs_rt.page->flags, __ATOMIC_RELAXED) & TCS_PAGE_QUEUED)
		goto park;
	for (unsigned i = 0;; i++) {
		uint32_t s = __atomic_load_n(&b->state, __ATOMIC_ACQUIRE);
		if ((s & TCS_MBOX_ANSWER) || *settled)
			return 1;
		if (s & TCS_MBOX_PARK)
			return 0;
		/* The clock every 64 turns: a vDSO read is some 30 ns. */
		if ((i & 63) == 0) {
			int64_t now = tcs_mailbox_clock();
			if (until == 0)
				until = now + TCS_MBOX_SPIN_NS;
			else if (now >= until)
				break;
		}
		tcs_cpu_relax();
	}
park:;
	uint32_t old = __atomic_fetch_or(&b->state, TCS_MBOX_PARK, __ATOMIC_ACQ_REL);
	return (old & TCS_MBOX_ANSWER) || *settled;
}

void tcs_mailbox_done(void)
{
	__atomic_store_n(&tcs_rt.page->mailbox.state, 0, __ATOMIC_RELEASE);
}
