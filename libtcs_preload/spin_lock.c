/* The runtime's locks (spin_lock.h), and all of them taken around a fork. */
#include "spin_lock.h"

int tcs_locks[TCS_LOCK_COUNT];

uint64_t tcs_locks_hold_all(void)
{
	uint64_t mask = tcs_signals_block();
	for (int i = 0; i < TCS_LOCK_COUNT; i++)
		(void)tcs_lock(&tcs_locks[i]); /* (signals are blocked already) */
	return mask;
}

void tcs_locks_release_all(uint64_t mask)
{
	for (int i = TCS_LOCK_COUNT - 1; i >= 0; i--)
		__atomic_store_n(&tcs_locks[i], 0, __ATOMIC_RELEASE);
	tcs_signals_restore(mask);
}
