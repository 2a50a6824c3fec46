/* The mailbox: one request and its answer handed over through the clock
 * page, without a system call, between a controller running on a core of
 * its own and the coordinator polling on its core. Through the channel a
 * hand-off costs two context switches or two inter-processor interrupts
 * (15-26 us on a VM, where one system call alone costs 1 us); through
 * shared memory both sides see it within a cache line's transfer (under
 * 1 us). The channel stays the way of everything else, and of the answer
 * whenever the controller stopped looking (it parked).
 *
 * Who uses it: the controller's main thread, while it has no other thread,
 * for requests whose answer is a plain WAKE (BLOCK with a deadline,
 * DEV_SYNC, TIMER, KILL), when the page says TCS_PAGE_MAILBOX.
 *
 * The hand-off, on `state`:
 *   controller   writes `request`, then state = REQUEST | BUSY; if `polling` is 0
 *                (read after that store) it rings: DOORBELL on its channel.
 *                Then it spins on state: ANSWER, the answer is in `answer`;
 *                PARK, it waits on its channel. Spun long enough, it sets
 *                PARK itself; if ANSWER was there first, it takes it.
 *   coordinator  takes a request (clears REQUEST), serves it; a request it
 *                cannot answer at once, it parks (sets PARK). To answer it
 *                writes `answer` and sets ANSWER; if PARK was set (by
 *                either side) it also sends the WAKE on the channel.
 *   controller   at the end of its round trip, state = 0. BUSY, which only
 *                it sets and clears, tells its own signal handler that the
 *                request is out (the coordinator's taking clears REQUEST):
 *                a handler that must make a request of its own parks the
 *                one it interrupted and takes its answer on the channel.
 * Exactly one of the two ways delivers each answer: whoever sets its bit
 * second sees the other's. `polling` is the coordinator's promise to look
 * without being rung: it clears it, then looks once more, before it sleeps.
 *
 * Everything in it comes from the controller as far as the coordinator is
 * concerned: it copies the request out before it checks it
 * (tcs_msg_check), and a flood of requests is a flood as on the channel. */
#ifndef TCS_MAILBOX_H
#define TCS_MAILBOX_H

#include <stdint.h>

#include "protocol.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TCS_MBOX_REQUEST 1u /* a request is posted, not yet taken */
#define TCS_MBOX_ANSWER 2u  /* the answer is in `answer` */
#define TCS_MBOX_PARK 4u    /* the answer goes on the channel */
#define TCS_MBOX_BUSY 8u    /* the controller's: posted, its round trip not over */

/* How long a controller spins for its answer before it parks: about what
 * parking and being woken cost on a slow machine. The coordinator parks a
 * request it cannot answer at once, so a spin this long is rare. */
#define TCS_MBOX_SPIN_NS 30000

/* Each part in a cache line of its own: the two sides write different ones. */
struct tcs_mailbox {
	uint32_t state;   /* TCS_MBOX_*: both sides, atomically */
	uint32_t polling; /* coordinator: it looks without being rung */
	uint8_t pad0[56];
	struct tcs_msg request; /* controller */
	uint8_t pad1[8];
	struct tcs_msg answer; /* coordinator */
	uint8_t pad2[8];
};

/* What a mailbox may carry: requests answered by a plain WAKE (no fd). */
static inline int tcs_mailbox_carries(uint16_t type)
{
	return type == TCS_MSG_BLOCK || type == TCS_MSG_DEV_SYNC || type == TCS_MSG_TIMER || type == TCS_MSG_KILL;
}

#if defined(__cplusplus)
static_assert(sizeof(struct tcs_mailbox) == 192, "mailbox layout changed: bump TCS_PAGE_VERSION");
#else
_Static_assert(sizeof(struct tcs_mailbox) == 192, "mailbox layout changed: bump TCS_PAGE_VERSION");
#endif

#ifdef __cplusplus
}
#endif
#endif
