/* The signal timers' table (signal_timers.h): what a timer is set to, in
 * virtual time. The hooks (hooks_timer.c) write it; helper threads
 * (timer_thread.c), a wait raising a timer's signal (wait.c) and a new
 * child (child.c) read or clear it. */
#include "signal_timers.h"
#include "spin_lock.h"

struct tcs_stimer tcs_stimers[TCS_MAX_TIMERS];

int tcs_stimer_copy(int slot, uint32_t gen, struct tcs_stimer *out)
{
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_STIMERS]);
	int alive = tcs_stimers[slot].used && tcs_stimers[slot].gen == gen;
	if (alive)
		*out = tcs_stimers[slot];
	tcs_unlock(&tcs_locks[TCS_LOCK_STIMERS], signals);
	return alive ? 0 : -1;
}

void tcs_stimer_set_overrun(int slot, uint32_t gen, int overrun)
{
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_STIMERS]);
	if (tcs_stimers[slot].gen == gen)
		tcs_stimers[slot].overrun = overrun;
	tcs_unlock(&tcs_locks[TCS_LOCK_STIMERS], signals);
}

void tcs_timers_forget_all(void)
{
	__builtin_memset(tcs_stimers, 0, sizeof tcs_stimers);
	for (int i = 0; i < TCS_MAX_TIMERS; i++)
		tcs_stimers[i].first = TCS_NEVER;
}

int tcs_timer_signal_target(int signo)
{
	for (int i = 0; i < TCS_MAX_TIMERS; i++)
		if (tcs_stimers[i].used && tcs_stimers[i].signo == signo && tcs_stimers[i].tid > 0)
			return tcs_stimers[i].tid;
	return 0;
}
