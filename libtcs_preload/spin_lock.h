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

/* Takes lock; returns the signal mask to give back to tcs_unlock. */
static inline uint64_t tcs_lock(int *lock)
{
	uint64_t mask = tcs_signals_block();
	for (unsigned i = 1; __atomic_exchange_n(lock, 1, __ATOMIC_ACQUIRE); i++) {
		if (i % 64 == 0)
			tcs_sys0(SYS_sched_yield);
		else
			tcs_cpu_relax();
	}
	return mask;
}

static inline void tcs_unlock(int *lock, uint64_t mask)
{
	__atomic_store_n(lock, 0, __ATOMIC_RELEASE);
	tcs_signals_restore(mask);
}

#endif
