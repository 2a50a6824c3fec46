/* The runtime's state (tcs_rt: whether this process is a controller, its
 * channel and clock page), which start-up fills (start.c), and the
 * conventions every file of this library follows.
 *
 * Rules for everything in this library (it runs inside someone else's
 * program, often in the middle of their signal handler):
 *   - no malloc, no stdio, no locks, no symbol lookup inside a hook (the
 *     real libc functions are looked up once, real.h);
 *   - talk to the kernel with tcs_sys*() (raw_syscall.h), never via errno;
 *   - internals return -errno; only the exported hook sets errno;
 *   - only hooks are exported (TCS_EXPORT), each in a hooks_*.c file;
 *     exports.txt lists them;
 *   - hooks call down into the runtime, never the runtime up into hooks. */
#ifndef TCS_PRELOAD_RUNTIME_H
#define TCS_PRELOAD_RUNTIME_H

#include <errno.h>
#include <stdint.h>

#include "tcs/clock_page.h"
#include "tcs/device_table.h"
#include "tcs/protocol.h"

#define TCS_EXPORT __attribute__((visibility("default")))
#define TCS_HIDDEN __attribute__((visibility("hidden")))

enum tcs_state {
	TCS_OFF = 0,      /* not initialised yet, or not under tcs-run: real time */
	TCS_ON = 1,       /* this process is a controller in virtual time */
	TCS_DETACHED = 2, /* a descendant the coordinator does not schedule */
};

struct tcs_runtime {
	int state;
	long pid; /* the controller's pid */
	int channel_fd;
	int page_fd;
	struct tcs_clock_page *page;
	const struct tcs_device_table *devices; /* beside the page, constant */
	struct tcs_journal *journal; /* --record, --replay: after them (tcs/journal.h) */
	uint32_t next_seq;
};

extern struct tcs_runtime tcs_rt TCS_HIDDEN;

static inline int tcs_active(void)
{
	return __atomic_load_n(&tcs_rt.state, __ATOMIC_RELAXED) == TCS_ON;
}

/* Whether two strings are equal (inline: no libc call inside a hook's
 * lookups, which run before libc's are resolved). */
static inline int tcs_str_equal(const char *a, const char *b)
{
	while (*a && *a == *b) {
		a++;
		b++;
	}
	return *a == *b;
}

/* Returns -1 with errno = -r when r < 0, else r. The one place hooks turn
 * internal -errno results into the C convention. */
static inline int tcs_errno_result(long r)
{
	if (r < 0) {
		errno = (int)-r;
		return -1;
	}
	return (int)r;
}

#endif
