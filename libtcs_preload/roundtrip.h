/* One request to the coordinator and its answer (roundtrip.c): on this
 * thread's channel, or through the clock page's mailbox. Round trips nest:
 * a signal handler's request ends the one it interrupted first. */
#ifndef TCS_PRELOAD_ROUNDTRIP_H
#define TCS_PRELOAD_ROUNDTRIP_H

#include <poll.h>
#include <signal.h>

#include "runtime.h"

/* Sends m on fd, or ends the program when the channel is gone (there is no
 * virtual time left to give it, and running on in real time would be a
 * silent lie). */
void tcs_send(int fd, const struct tcs_msg *m) TCS_HIDDEN;

/* Sends m (its seq is assigned here) and waits for the WAKE answering it,
 * in ppoll over the channel and fds[1..nfds-1] (fds may be NULL) with the
 * signal mask `mask`. A real fd becoming ready or a signal handler running
 * first sends EARLY (and the WAKE still comes). Returns the EARLY reason
 * sent, or 0; the WAKE in *reply; an fd passed with it in *fd_out (or
 * closed when fd_out is NULL). */
unsigned tcs_roundtrip(struct tcs_msg *m, struct pollfd *fds, unsigned nfds, const sigset_t *mask,
		       struct tcs_msg *reply, int *fd_out) TCS_HIDDEN;

/* Asked for the round trip of m on this thread (a handler's own, run
 * before or inside it, does not take it): if its answer is a RECHECK, nothing having
 * ended it early, it returns with every signal still blocked and the mask
 * from before in *held, and *holding set. A wait that goes on after a
 * re-check is inside the program's call: a handler must run only where the
 * wait notices it (wait.c), not in the gap before it is asked again. */
void tcs_roundtrip_hold_on_recheck(const struct tcs_msg *m, uint64_t *held, int *holding) TCS_HIDDEN;

/* This thread's round trips under way, the innermost first: set only
 * while one is (a clock read checks it on its way, spin.h). */
extern __thread struct tcs_call *tcs_calls TCS_HIDDEN __attribute__((tls_model("initial-exec")));

/* A signal handler reads the clock inside this thread's round trip: the
 * round trip is ended first (as a handler's own request ends it), so that
 * the clock reads the time the handler runs at, which only the answer
 * says (a signal from another controller acts at the sender's time; the
 * page still holds the time before the wait); one answered to re-check
 * is ended by the handler all the same. */
void tcs_settle_for_clock(void) TCS_HIDDEN;

/* In a forked child: the round trips the forking flow was inside (a fork
 * from a signal handler) were its parent's; they end at the fork's
 * virtual time v, as if a signal had interrupted them. */
void tcs_calls_after_fork(int64_t v) TCS_HIDDEN;

#endif
