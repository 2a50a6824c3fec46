/* SIGEV_THREAD timers in virtual time. Each such timer has a helper thread
 * of the program's (made with the timer's sigev_notify_attributes) that
 * waits in a hooked condition-variable wait until the timer's next expiry,
 * so the coordinator ends that wait at the expiry's virtual time, and then
 * calls the notify function. glibc starts a new thread for every expiry
 * instead; here the calls of one timer follow each other on its helper,
 * and expiries that pass while a call runs are counted as its successor's
 * overrun (timer_getoverrun), as the kernel counts them for a signal that
 * is still pending. A helper waits and wakes through the hooks, by their
 * public names, as any thread of the program does. */
#include <pthread.h>

#include "signal_mask.h"
#include "signal_timers.h"
#include "timer_thread.h"
#include "vclock.h"

/* One lock and condition for all helpers: timer changes are rare, and each
 * helper re-reads its own timer when woken. */
static pthread_mutex_t tcs_helpers_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t tcs_helpers_cond = PTHREAD_COND_INITIALIZER;

#define TCS_HELPER_ARG(slot, gen) ((void *)(uintptr_t)((uint64_t)(gen) << 16 | (unsigned)(slot)))

static void *tcs_timer_thread(void *arg)
{
	int slot = (int)((uintptr_t)arg & 0xffff);
	uint32_t gen = (uint32_t)((uintptr_t)arg >> 16);
	/* Signals are for the program's own threads, as with glibc's helper. */
	sigset_t all;
	sigfillset(&all);
	pthread_sigmask(SIG_BLOCK, &all, NULL);

	uint32_t seen_sets = ~0u;
	int64_t next = TCS_NEVER; /* the expiry to notify next */
	pthread_mutex_lock(&tcs_helpers_lock);
	for (;;) {
		struct tcs_stimer t;
		if (tcs_stimer_copy(slot, gen, &t) < 0)
			break;
		if (t.set_count != seen_sets) {
			seen_sets = t.set_count;
			next = t.first; /* (re)armed: its first expiry, even one already past */
		}
		if (next == TCS_NEVER) {
			pthread_cond_wait(&tcs_helpers_cond, &tcs_helpers_lock);
			continue;
		}
		int64_t now = tcs_vnow();
		if (now < next) {
			/* Until the expiry, or a change: then look again. */
			struct timespec at = tcs_ns_to_ts(tcs_sleep_clock_origin(CLOCK_MONOTONIC) + next);
			pthread_cond_clockwait(&tcs_helpers_cond, &tcs_helpers_lock, CLOCK_MONOTONIC, &at);
			continue;
		}
		/* Due: one call for every expiry up to now. */
		int overrun = 0;
		if (t.interval > 0 && now - next >= t.interval) {
			int64_t k = (now - next) / t.interval;
			overrun = k > INT32_MAX ? INT32_MAX : (int)k;
			next += k * t.interval;
		}
		tcs_stimer_set_overrun(slot, gen, overrun);
		pthread_mutex_unlock(&tcs_helpers_lock);
		t.notify(t.value);
		pthread_mutex_lock(&tcs_helpers_lock);
		next = tcs_stimer_next(&t, next);
	}
	pthread_mutex_unlock(&tcs_helpers_lock);
	return NULL;
}

int tcs_timer_thread_start(int slot, uint32_t gen, const struct sigevent *sev)
{
	pthread_attr_t *attr = (pthread_attr_t *)sev->sigev_notify_attributes;
	int detached = 0;
	if (attr && pthread_attr_getdetachstate(attr, &detached) == 0)
		detached = detached == PTHREAD_CREATE_DETACHED;
	pthread_t th;
	int r = pthread_create(&th, attr, tcs_timer_thread, TCS_HELPER_ARG(slot, gen));
	if (r != 0)
		return -r;
	if (!detached)
		pthread_detach(th);
	return 0;
}

void tcs_timer_threads_poke(void)
{
	/* Signals blocked, as in the helpers: a handler that sets a timer
	 * here again never finds the lock held by the flow it interrupted. */
	uint64_t open = tcs_signals_block();
	pthread_mutex_lock(&tcs_helpers_lock);
	pthread_cond_broadcast(&tcs_helpers_cond);
	pthread_mutex_unlock(&tcs_helpers_lock);
	tcs_signals_restore(open);
}
