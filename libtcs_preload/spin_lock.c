/* The runtime's locks (spin_lock.h), and all of them taken around a fork. */
#include "spin_lock.h"

#include <time.h>

#include "report.h"

int tcs_locks[TCS_LOCK_COUNT];

/* Held longer than this, a lock is never let go (held for a few loads and
 * stores, it is free within microseconds, or a scheduler tick's wait). */
#define TCS_LOCK_HELD_TOO_LONG (5 * TCS_NS_PER_S)

void tcs_lock_held_long(const int *lock, int64_t *since)
{
	static const char *const names[TCS_LOCK_COUNT] = { "signal timers", "timerfds", "thread channels",
							   "timer slack notes", "parked threads" };
	struct timespec ts;
	tcs_sys2(SYS_clock_gettime, CLOCK_MONOTONIC, &ts);
	int64_t now = (int64_t)ts.tv_sec * TCS_NS_PER_S + ts.tv_nsec;
	if (*since == 0) {
		*since = now;
		return;
	}
	if (now - *since < TCS_LOCK_HELD_TOO_LONG)
		return;
	long i = lock - tcs_locks;
	tcs_say("a lock of the runtime (", i >= 0 && i < TCS_LOCK_COUNT ? names[i] : "?",
		") has been held for 5 s: a defect of tcs (please report it, with the command line)");
	for (;;)
		tcs_sys1(SYS_exit_group, 2);
}

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
