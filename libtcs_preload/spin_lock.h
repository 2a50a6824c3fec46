/* The runtime's one kind of lock, for its small tables (thread channels,
 * parked threads, timers, timer slack): held for a few loads and stores
 * with every signal blocked, so a signal handler's hook that takes the same
 * lock never finds it held by the flow it interrupted (docs/DESIGN.md,
 * "Re-entrancy"). Another thread holding it may share our core: after a
 * few turns the spinner yields. No other lock exists in this library:
 * tests/preload_layout.py checks that nothing else spins on one. */
#ifndef TCS_PRELOAD_SPIN_LOCK_H
#define TCS_PRELOAD_SPIN_LOCK_H

#include "raw_syscall.h"
#include "signal_mask.h"
#include "tcs/clock_page.h"

/* Every lock of the runtime, in the order a fork takes them all
 * (tcs_locks_hold_all): no code holds one while it takes another. */
enum {
	TCS_LOCK_STIMERS,    /* signal timers (signal_timers.c, hooks_timer.c) */
	TCS_LOCK_TIMERFDS,   /* virtual timerfds (timerfds.c) */
	TCS_LOCK_THREAD_FDS, /* threads' channels (thread_channels.c) */
	TCS_LOCK_SLACK_NOTES, /* timer slack notes (timer_slack.c) */
	TCS_LOCK_PARKED,     /* parked threads (parking.c) */
	TCS_LOCK_COUNT
};
extern int tcs_locks[TCS_LOCK_COUNT] __attribute__((visibility("hidden")));

/* Waited for seconds, a lock is held by a flow that will never let it go:
 * a defect of tcs, said on stderr, and the process ends with status 2
 * rather than spin for ever. *since: 0, then when the wait was first
 * looked at. */
void tcs_lock_held_long(const int *lock, int64_t *since) __attribute__((visibility("hidden")));

/* Takes lock; returns the signal mask to give back to tcs_unlock. */
static inline uint64_t tcs_lock(int *lock)
{
	uint64_t mask = tcs_signals_block();
	int64_t since = 0;
	for (unsigned i = 1; __atomic_exchange_n(lock, 1, __ATOMIC_ACQUIRE); i++) {
		if (i % 64 == 0) {
			tcs_sys0(SYS_sched_yield);
			if (i % (64u << 12) == 0) /* some milliseconds */
				tcs_lock_held_long(lock, &since);
		} else {
			tcs_cpu_relax();
		}
	}
	return mask;
}

static inline void tcs_unlock(int *lock, uint64_t mask)
{
	__atomic_store_n(lock, 0, __ATOMIC_RELEASE);
	tcs_signals_restore(mask);
}

/* Around a fork: the forking thread holds every lock, so that no other
 * thread is halfway through a table the child inherits (a child spun for
 * ever on the timers' lock, held at the fork by a thread that the child
 * does not have); both sides then let them go. */
uint64_t tcs_locks_hold_all(void) __attribute__((visibility("hidden")));
void tcs_locks_release_all(uint64_t mask) __attribute__((visibility("hidden")));

#endif
