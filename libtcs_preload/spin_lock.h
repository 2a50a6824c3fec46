/* A spin lock for the runtime's small tables (thread channels, parked
 * threads, timers): held for a few loads and stores; threads of a
 * controller share one core, so it is rarely seen. */
#ifndef TCS_PRELOAD_SPIN_LOCK_H
#define TCS_PRELOAD_SPIN_LOCK_H

#include "tcs/clock_page.h"

static inline void tcs_spin_lock(int *lock)
{
	while (__atomic_exchange_n(lock, 1, __ATOMIC_ACQUIRE))
		tcs_cpu_relax();
}

static inline void tcs_spin_unlock(int *lock)
{
	__atomic_store_n(lock, 0, __ATOMIC_RELEASE);
}

#endif
