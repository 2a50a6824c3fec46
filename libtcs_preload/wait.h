/* Waiting in virtual time (wait.c): entering and leaving a blocking hook,
 * the wait itself, and the news of signals sent to other processes, which
 * a handler inside a wait leaves for the wait's end. */
#ifndef TCS_PRELOAD_WAIT_H
#define TCS_PRELOAD_WAIT_H

#include <poll.h>
#include <signal.h>

#include "runtime.h"
#include "thread_waits.h"

enum tcs_wait_result {
	TCS_WAIT_DEADLINE = 0, /* the deadline was reached */
	TCS_WAIT_FD = 1,       /* one of the real fds became ready first */
	TCS_WAIT_RECHECK = 2,  /* a step passed; re-check real fds and wait again */
};

/* When a wait is to end, and when it began and ended (virtual ns). */
struct tcs_wait_time {
	int64_t deadline; /* in: absolute, or the timeout if relative; out: absolute */
	int relative;     /* in: deadline is a timeout from the start of the wait */
	int64_t start;    /* out: when the wait began */
	int64_t end;      /* out: when it ended */
	uint32_t seq;     /* in: a sequence number reserved for it (parking.c), or 0 */
	int64_t slack;    /* in: how long after the deadline it ends, when nothing ends it
			     sooner (timer_slack.h; 0: at the deadline) */
};

/* Signals held blocked across a wait's re-checks (tcs_wait_held). */
struct tcs_wait_hold {
	int holding;   /* every signal is blocked: a RECHECK came */
	uint64_t mask; /* the mask before, each later wait's own */
};

/* Waits until the virtual deadline (TCS_NEVER: forever). With fds, the wait
 * also ends when one of fds[1..nfds-1] becomes ready; fds[0] is reserved for
 * the channel and mask (may be NULL) is the signal mask during the wait.
 * Returns a tcs_wait_result or -EINTR when a signal handler ran. A deadline
 * already past returns at once without a round trip. The start of the wait
 * is read once, for both the deadline and the BLOCK: one CPU-clock read. */
int tcs_wait(struct tcs_wait_time *t, unsigned kind, unsigned flags, struct pollfd *fds, unsigned nfds,
	     const sigset_t *mask) TCS_HIDDEN;

/* tcs_wait without fds for a wait that goes on after a re-check: the first
 * RECHECK returns with every signal blocked (h->holding, the mask before in
 * h->mask), and each later wait lets them in by its own look and ppoll with
 * h->mask, as sigsuspend does; the caller gives the mask back at the end
 * (tcs_wait_unhold). Inside the program's call, a handler then runs only
 * where a wait notices it and ends the call (-EINTR): let in between the
 * RECHECK and the next wait (through the mailbox's spin, say), it went
 * unnoticed. */
long tcs_wait_held(struct tcs_wait_time *t, struct tcs_wait_hold *h, unsigned kind, unsigned flags) TCS_HIDDEN;
void tcs_wait_unhold(struct tcs_wait_hold *h) TCS_HIDDEN;

/* Stepped aside by the coordinator (TCS_PAGE_ASLEEP) and awake again: asks
 * the world's time before a clock read answers (tcs_vnow). */
void tcs_catch_up(void) TCS_HIDDEN;

/* Before a send of sig to target (kill's convention: a pid, -pgid, or -1
 * when not at hand): one to another process is told to the coordinator
 * (TCS_MSG_KILL), so that a controller waiting in virtual time acts on it
 * at the sender's time. Told first: the receiver's wait, ended by the
 * signal, must not reach the coordinator before the news of it does (its
 * handler then ran at the world's time, before the sender's). From a
 * handler inside a wait too: the wait is ended first (roundtrip.c). */
void tcs_signal_sending(long target, int sig) TCS_HIDDEN;

/* After a send of sig to target (as tcs_signal_sending's; to thread tid
 * of it, or 0): one that reached this process and may be another thread's
 * is told to the coordinator (TCS_MSG_KILL of this pid), which ends the
 * waits of the other threads at the sender's time, to re-check. Told
 * after: the signal is then pending when a thread re-checks, and the
 * sender, which runs until the answer, keeps virtual time from passing
 * before the receiver's handler has asked for its own (else a wait in the
 * handler began at the world's next step, up to a wait late). Nothing for
 * a process without threads. */
void tcs_signal_sent(long target, long tid, int sig) TCS_HIDDEN;

#endif
