/* The mailbox hand-off, the controller's side (mailbox.c, tcs/mailbox.h). */
#ifndef TCS_PRELOAD_MAILBOX_H
#define TCS_PRELOAD_MAILBOX_H

#include "runtime.h"

/* May request m, about to go on channel, go through the mailbox? */
int tcs_mailbox_fits(const struct tcs_msg *m, int channel) TCS_HIDDEN;
/* Posts m; non-zero when the coordinator is not polling and must be rung
 * (DOORBELL on the channel). */
int tcs_mailbox_post(const struct tcs_msg *m) TCS_HIDDEN;
/* Spins for the answer: 1 with it in *reply, or 0 when parked (the answer
 * comes on the channel). */
int tcs_mailbox_wait(struct tcs_msg *reply) TCS_HIDDEN;
/* The round trip is over, whichever way its answer came: the mailbox is free. */
void tcs_mailbox_done(void) TCS_HIDDEN;

#endif
