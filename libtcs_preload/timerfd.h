/* Virtual timerfds (timerfd.c): what the fd, read and multiplexer hooks
 * need to know of them. */
#ifndef TCS_TIMERFD_H
#define TCS_TIMERFD_H

#include "runtime.h"

/* Whether fd is a virtual timerfd. */
int tcs_vtimer_of(int fd) TCS_HIDDEN;
/* Makes every timer due at virtual time v readable (its expirations counted
 * into its fd); returns the earliest expiry still to come (TCS_NEVER: none). */
int64_t tcs_vtimers_fire(int64_t v) TCS_HIDDEN;
/* Whether any virtual timer is armed (then multiplexers wake for them). */
int tcs_vtimers_armed(void) TCS_HIDDEN;
/* read(2) on a virtual timerfd: the expiration count, or -errno. */
long tcs_vtimer_read(int fd, void *buf, size_t n) TCS_HIDDEN;
/* fd was closed / to became a copy of from. */
void tcs_vtimer_forget(int fd) TCS_HIDDEN;
void tcs_vtimer_copy(int from, int to) TCS_HIDDEN;

#endif
