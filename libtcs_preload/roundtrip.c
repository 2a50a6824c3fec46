/* One request to the coordinator and its answer (roundtrip.h). Every
 * request of this library goes through tcs_roundtrip: a wait's BLOCK, a
 * device's sync, a timer, a child, a signal's news. Runs inside hooks,
 * signal handlers included, and nests: a handler's request may interrupt
 * another of the same thread (docs/DESIGN.md, "Re-entrancy").
 *
 * A thread has at most one request out at a time (protocol.h). Each round
 * trip is a call frame on this thread's stack, the innermost first
 * (tcs_calls). A handler's request first settles the one it interrupted:
 * ends it (EARLY: a handler ran, as a real wait would be ended) and takes
 * its WAKE into that frame, so the interrupted round trip finds itself
 * answered when the handler returns; only then does its own go out.
 *
 * What a handler may see of a frame is made so that it can tell where the
 * frame stands:
 *   - on the channel, everything from the send to the answer's taking runs
 *     with every signal blocked, except the ppoll that waits, so a handler
 *     runs only there: its frame was sent and not yet answered;
 *   - in the mailbox (no system call at all), the mailbox's state says:
 *     TCS_MBOX_BUSY posted, ANSWER answered; a handler parks the request to
 *     take it over on the channel.
 * An answer is received straight into its frame, in one system call: there
 * is no moment at which it is taken but not yet where its frame sees it. */
#include <sys/socket.h>

#include "cpu_estimate.h"
#include "journal_write.h"
#include "lazy_writes.h"
#include "mailbox_post.h"
#include "raw_syscall.h"
#include "report.h"
#include "roundtrip.h"
#include "signal_mask.h"
#include "tcs/msg_io.h"
#include "thread_channels.h"

/* A round trip under way on this thread. */
struct tcs_call {
	struct tcs_call *outer; /* the round trip a handler interrupted for this one */
	uint32_t seq;
	uint8_t in_mailbox; /* it goes (or went) by the mailbox */
	uint8_t sent;       /* on the channel: sent (set with signals blocked) */
	uint8_t early;      /* the EARLY reason sent for it, or 0 */
	uint8_t answered;   /* its WAKE is in reply */
	uint8_t forked;     /* a forked child's copy of its parent's: ended at the fork */
	int channel;
	struct tcs_msg reply;
	struct tcs_msg_io io; /* receives into reply: an fd with it lands here */
};

__thread struct tcs_call *tcs_calls;

/* tcs_roundtrip_hold_on_recheck's request, for the round trip of message
 * tcs_hold_msg only: a handler that runs between the request and that
 * round trip makes its own with another message, which leaves it. */
static __thread const struct tcs_msg *tcs_hold_msg;
static __thread uint64_t *tcs_hold_mask;
static __thread int *tcs_hold_flag;

void tcs_roundtrip_hold_on_recheck(const struct tcs_msg *m, uint64_t *held, int *holding)
{
	tcs_hold_mask = held;
	tcs_hold_flag = holding;
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	tcs_hold_msg = m;
}

/* The coordinator is gone or spoke nonsense: there is no virtual time left
 * to give this program, and running on in real time would be a silent lie. */
static __attribute__((noreturn)) void tcs_lost(const char *why)
{
	tcs_say("lost the coordinator: ", why, NULL);
	tcs_sys2(SYS_kill, tcs_sys0(SYS_getpid), SIGKILL);
	for (;;)
		tcs_sys1(SYS_exit_group, 2);
}

void tcs_send(int fd, const struct tcs_msg *m)
{
	long r;
	do
		r = tcs_sys6(SYS_sendto, fd, (long)m, sizeof *m, MSG_NOSIGNAL, 0, 0);
	while (r == -EINTR);
	if (r != (long)sizeof *m)
		tcs_lost("the channel is closed");
}

static void tcs_send_early(struct tcs_call *c, unsigned reason)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_EARLY, c->seq);
	m.kind = (uint16_t)reason;
	tcs_send(c->channel, &m);
	c->early = (uint8_t)reason;
}

/* Receives on c's channel until c's WAKE is there (signals blocked, or in a
 * handler's settling; fds and mask: the caller's wait, as for ppoll). */
static void tcs_await(struct tcs_call *c, struct pollfd *fds, unsigned nfds, const uint64_t *mask, int look_first)
{
	struct pollfd own;
	if (!fds) {
		fds = &own;
		nfds = 1;
	}
	while (!c->answered) {
		/* Wait in ppoll, never in a blocking recv: ppoll is the one wait
		 * the kernel never restarts after a signal handler, SA_RESTART or
		 * not (so a handler is noticed, as a real sleep would be), and
		 * always restarts transparently after the coordinator's
		 * SIGSTOP/SIGCONT. Its mask is where handlers run. Once the EARLY
		 * is out only the channel counts: the WAKE is on its way. Each
		 * second of real time without it is counted in the page: a wait
		 * the coordinator does not know it owes is a defect it reports
		 * rather than a hang (coordinator/stuck.cc). */
		if (!look_first) {
			/* (Writable: the kernel writes back what is left, and
			 * restarts the wait after a stop only if it can.) */
			struct timespec check = { 1, 0 };
			fds[0].fd = c->channel;
			fds[0].events = POLLIN;
			fds[0].revents = 0;
			long r = tcs_sys5(SYS_ppoll, fds, c->early ? 1 : nfds, &check, mask,
					  TCS_KERNEL_SIGSET_SIZE);
			if (c->answered)
				break; /* a handler that ran settled it */
			if (r == -EINTR) {
				if (!c->early)
					tcs_send_early(c, TCS_EARLY_SIGNAL);
				continue;
			}
			if (r < 0)
				tcs_lost("ppoll on the channel failed");
			if (r == 0) {
				if (tcs_rt.page)
					__atomic_add_fetch(&tcs_rt.page->unanswered, 1, __ATOMIC_RELAXED);
				continue;
			}
			if (fds[0].revents == 0) {
				if (!c->early)
					tcs_send_early(c, TCS_EARLY_FD);
				continue;
			}
		}
		tcs_msg_io_recv(&c->io, &c->reply, sizeof c->reply);
		c->reply.seq = 0;
		long r = tcs_sys3(SYS_recvmsg, c->channel, &c->io.mh, MSG_CMSG_CLOEXEC | (look_first ? MSG_DONTWAIT : 0));
		if (look_first) {
			look_first = 0;
			if (r == -EAGAIN)
				continue; /* not yet: wait for it in ppoll */
		}
		if (r == -EINTR)
			continue;
		if (r != (long)sizeof c->reply || c->reply.magic != TCS_PROTO_MAGIC || c->reply.type != TCS_MSG_WAKE)
			tcs_lost(r == 0 ? "the channel is closed" : "unexpected message");
		if (c->reply.seq == c->seq) {
			c->answered = 1;
			break;
		}
		/* An answer nobody waits for: its fd, if any, is nobody's. */
		int fd = tcs_msg_io_fd(&c->io);
		if (fd >= 0)
			tcs_sys1(SYS_close, fd);
	}
}

/* The answer is in the mailbox: into c. */
static void tcs_mailbox_answered(struct tcs_call *c)
{
	tcs_mailbox_take(&c->reply);
	c->answered = 1;
}

/* A handler's request is about to go out on this thread, whose round trip
 * c it interrupted: c is ended and answered first (signals blocked). */
static void tcs_settle(struct tcs_call *c)
{
	if (!c || c->answered)
		return;
	if (c->in_mailbox) {
		uint32_t was = tcs_mailbox_park_now();
		if (was & TCS_MBOX_ANSWER) {
			tcs_mailbox_answered(c);
			return;
		}
		if (!(was & TCS_MBOX_BUSY)) {
			tcs_mailbox_unpark(); /* not posted yet: it goes when the handler is done */
			return;
		}
		/* Parked: its WAKE comes on the channel. */
	} else if (!c->sent) {
		return; /* not sent yet: it goes when the handler is done */
	}
	if (!c->early)
		tcs_send_early(c, TCS_EARLY_SIGNAL);
	uint64_t none = ~0ull; /* (nothing may interrupt the settling) */
	tcs_await(c, NULL, 0, &none, 0);
}

/* c was answered RECHECK, and nothing ended it early. */
static int tcs_rechecks(const struct tcs_call *c)
{
	return c->answered && !c->early && c->reply.kind == TCS_WAKE_RECHECK;
}

void tcs_settle_for_clock(void)
{
	struct tcs_call *c = __atomic_load_n(&tcs_calls, __ATOMIC_RELAXED);
	if (!c)
		return;
	if (!c->answered) {
		uint64_t open = tcs_signals_block();
		tcs_settle(c);
		tcs_signals_restore(open);
	}
	/* Answered to re-check (a signal was on its way) before its caller
	 * could block signals: this handler is that signal, and the wait
	 * ends with it rather than going on (the mailbox's path, where
	 * signals are open until the answer is taken). */
	if (tcs_rechecks(c))
		c->early = TCS_EARLY_SIGNAL;
}

/* Signals stay blocked: the mask before them for the caller. */
static void tcs_hold(uint64_t *held, int *holding, uint64_t open)
{
	*held = open;
	*holding = 1;
}

/* The WAKE in c, returned. */
static void tcs_hand_over(struct tcs_call *c, struct tcs_msg *reply, int *fd_out)
{
	*reply = c->reply;
	int fd = c->in_mailbox || c->forked ? -1 : tcs_msg_io_fd(&c->io);
	if (fd_out)
		*fd_out = fd;
	else if (fd >= 0)
		tcs_sys1(SYS_close, fd);
}

unsigned tcs_roundtrip(struct tcs_msg *m, struct pollfd *fds, unsigned nfds, const sigset_t *mask,
		       struct tcs_msg *reply, int *fd_out)
{
	uint32_t seq = m->seq ? m->seq : __atomic_add_fetch(&tcs_rt.next_seq, 1, __ATOMIC_RELAXED);
	m->seq = seq;
	struct tcs_call c;
	__builtin_memset(&c, 0, sizeof c);
	c.seq = seq;
	c.channel = tcs_my_channel();
	if (c.channel < 0)
		tcs_lost("this thread has no channel");
	if (fd_out)
		*fd_out = -1;
	c.outer = tcs_calls;
	uint64_t *hold = NULL;
	int *holding = NULL;
	if (tcs_hold_msg == m) {
		hold = tcs_hold_mask;
		holding = tcs_hold_flag;
		tcs_hold_msg = NULL;
	}
	/* On a core of its own, beside the coordinator polling on its own: no
	 * system call at all, unless it must be rung or the answer is slow.
	 * Not for a handler's request: the mailbox is its interrupted one's. */
	c.in_mailbox = !c.outer && !fds && !mask && !fd_out && tcs_mailbox_fits(m, c.channel);
	uint64_t open = 0;
	if (c.in_mailbox) {
		__atomic_store_n(&tcs_calls, &c, __ATOMIC_RELAXED);
		__atomic_signal_fence(__ATOMIC_SEQ_CST);
		if (tcs_mailbox_post(m)) {
			struct tcs_msg ring = tcs_msg_make(TCS_MSG_DOORBELL, seq);
			tcs_send(c.channel, &ring);
		}
		tcs_lazy_request_sent();
		if (tcs_mailbox_wait(&c.answered)) {
			if (!c.answered)
				tcs_mailbox_answered(&c);
			if (hold && tcs_rechecks(&c))
				tcs_hold(hold, holding, tcs_signals_block());
		} else if (!c.answered) {
			/* Parked: the answer comes on the channel. */
			open = tcs_signals_block();
			tcs_await(&c, NULL, 0, &open, 0);
			if (hold && tcs_rechecks(&c))
				tcs_hold(hold, holding, open);
			else
				tcs_signals_restore(open);
		}
	} else {
		open = tcs_signals_block();
		tcs_settle(c.outer);
		__atomic_store_n(&tcs_calls, &c, __ATOMIC_RELAXED);
		tcs_send(c.channel, m);
		c.sent = 1;
		tcs_lazy_request_sent();
		/* Under SCHED_FIFO on our core the coordinator ran as soon as we
		 * sent: a reply it could give at once is already there. */
		const uint32_t here = TCS_PAGE_FIFO | TCS_PAGE_SHARES_CORE;
		int look_first = (__atomic_load_n(&tcs_rt.page->flags, __ATOMIC_RELAXED) & here) == here;
		tcs_await(&c, fds, nfds, mask ? (const uint64_t *)(const void *)mask : &open, look_first);
		if (hold && tcs_rechecks(&c))
			tcs_hold(hold, holding, open);
		else
			tcs_signals_restore(open);
	}
	if (c.in_mailbox)
		tcs_mailbox_done();
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	__atomic_store_n(&tcs_calls, c.outer, __ATOMIC_RELAXED);
	tcs_hand_over(&c, reply, fd_out);
	if (c.reply.seq != seq || c.reply.type != TCS_MSG_WAKE)
		tcs_lost("unexpected answer in the mailbox");
	if (__builtin_expect(tcs_journal_on(), 0))
		tcs_journal_answered(m->type, reply->deadline);
	/* From here on the hook's own cost is not charged to the program. The
	 * mark is the process's CPU, which only means this hook's cost while
	 * the process has one thread: with more, another may have computed
	 * between the coordinator's resume and this thread's turn, and that is
	 * theirs to be charged (as on_block charges a threaded BLOCK to the
	 * coordinator's reading, not the hook's entry). */
	if ((reply->flags & TCS_WAKE_STARTS_SLICE) &&
	    __atomic_load_n(&tcs_rt.page->threads_started, __ATOMIC_RELAXED) == 0) {
		__atomic_store_n(&tcs_rt.page->exit_cpu, tcs_exit_mark(m->cpu), __ATOMIC_RELAXED);
		tcs_anchor_forget_v(); /* a read in between saw the old mark */
	}
	return c.early;
}

void tcs_calls_after_fork(int64_t v)
{
	/* The round trips the forking flow was inside (a handler's fork) were
	 * its parent's: each ends here, at the fork's time, as one a signal
	 * interrupted. */
	for (struct tcs_call *c = tcs_calls; c; c = c->outer) {
		if (c->answered)
			continue;
		struct tcs_msg w = tcs_msg_make(TCS_MSG_WAKE, c->seq);
		w.kind = TCS_WAKE_EARLY;
		w.v = v;
		w.deadline = v;
		c->reply = w;
		c->forked = 1;
		c->early = TCS_EARLY_SIGNAL;
		c->answered = 1;
	}
}
