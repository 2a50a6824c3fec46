/* Virtual timerfds (timerfds.c): the table of timers and the fds that refer
 * to them, which the fd, multiplexer and timerfd hooks keep. */
#ifndef TCS_PRELOAD_TIMERFDS_H
#define TCS_PRELOAD_TIMERFDS_H

#include <time.h>

#include "fd_table.h"
#include "runtime.h"

struct tcs_vtimer {
	int refs;         /* fds referring to it; 0: a free slot */
	int fd;           /* one of them, to write expirations into */
	clockid_t clock;  /* for absolute times and gettime */
	int64_t next;     /* virtual ns of the next expiry; TCS_NEVER: disarmed */
	int64_t interval; /* 0: one-shot */
};

/* The virtual timer fd refers to, or NULL: fd is no virtual timerfd. */
struct tcs_vtimer *tcs_vtimer_of(int fd) TCS_HIDDEN;
/* fd (an eventfd below TCS_FD_MAX) becomes a disarmed timer on
 * clock: 0, or -EMFILE when the table is full. */
int tcs_vtimer_add(int fd, clockid_t clock) TCS_HIDDEN;
/* What is left of t at virtual time now, and its interval. */
struct itimerspec tcs_vtimer_value(const struct tcs_vtimer *t, int64_t now) TCS_HIDDEN;
/* Arms t for virtual time next (TCS_NEVER: disarms it) and every interval
 * after; *old (may be NULL) gets what was left at now. */
void tcs_vtimer_arm(struct tcs_vtimer *t, int64_t next, int64_t interval, int64_t now, struct itimerspec *old) TCS_HIDDEN;
/* Makes every timer due at virtual time v readable (its expirations counted
 * into its fd); returns the earliest expiry still to come (TCS_NEVER: none). */
int64_t tcs_vtimers_fire(int64_t v) TCS_HIDDEN;
/* Whether any virtual timer is armed (then multiplexers wake for them). */
int tcs_vtimers_armed(void) TCS_HIDDEN;
/* Reads fd's expiration count without blocking: 8, or -EAGAIN. */
long tcs_vtimer_drain(int fd, void *buf) TCS_HIDDEN;

/* The kind's operations (fd_table.h): read(2) is the expiration count, in
 * virtual time. */
extern const struct tcs_fd_ops tcs_timerfd_ops TCS_HIDDEN;

#endif
