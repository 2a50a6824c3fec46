/* The mailbox hand-off, the controller's side (mailbox_post.c, tcs/mailbox.h). */
#ifndef TCS_PRELOAD_MAILBOX_POST_H
#define TCS_PRELOAD_MAILBOX_POST_H

#include "runtime.h"

/* May request m, about to go on channel, go through the mailbox? */
int tcs_mailbox_fits(const struct tcs_msg *m, int channel) TCS_HIDDEN;
/* Posts m; non-zero when the coordinator is not polling and must be rung
 * (DOORBELL on the channel). */
int tcs_mailbox_post(const struct tcs_msg *m) TCS_HIDDEN;
/* Spins for the answer: 1 when it is in the mailbox or *settled was set
 * (by a signal handler that took it), 0 when parked (the answer comes on
 * the channel). */
int tcs_mailbox_wait(const volatile uint8_t *settled) TCS_HIDDEN;
/* The answer, copied out. */
void tcs_mailbox_take(struct tcs_msg *reply) TCS_HIDDEN;
/* A signal handler parks the request it interrupted: the state before
 * (TCS_MBOX_*); one not posted yet (no BUSY) is unparked again. */
uint32_t tcs_mailbox_park_now(void) TCS_HIDDEN;
void tcs_mailbox_unpark(void) TCS_HIDDEN;
/* The round trip is over, whichever way its answer came: the mailbox is free. */
void tcs_mailbox_done(void) TCS_HIDDEN;

#endif
