/* The signal timers' table (signal_timers.c): the runtime's record of each
 * timer, which the timer hooks (hooks_timer.c) keep, the helper threads of
 * SIGEV_THREAD timers (timer_thread.c) follow, and a wait consults when
 * the coordinator says a timer's signal is due (wait.c). */
#ifndef TCS_PRELOAD_SIGNAL_TIMERS_H
#define TCS_PRELOAD_SIGNAL_TIMERS_H

#include <signal.h>

#include "runtime.h"

struct tcs_stimer {
	int used;
	int signo;        /* 0: SIGEV_NONE or SIGEV_THREAD */
	int tid;          /* SIGEV_THREAD_ID: the thread; 0: the process */
	clockid_t clock;  /* for absolute times */
	int64_t first;    /* virtual ns of the first expiry; TCS_NEVER: disarmed */
	int64_t interval; /* 0: once */
	/* SIGEV_THREAD: what to call, the timer's incarnation (a slot is used
	 * again after timer_delete), how often it was set, and the overrun of
	 * the last call. */
	void (*notify)(union sigval);
	union sigval value;
	uint32_t gen;
	uint32_t set_count;
	int overrun;
};

/* The next expiry after virtual time v (TCS_NEVER: none): strictly after v
 * once the first has passed. */
static inline int64_t tcs_stimer_next(const struct tcs_stimer *t, int64_t v)
{
	if (t->first == TCS_NEVER || v < t->first)
		return t->first;
	if (t->interval <= 0)
		return TCS_NEVER;
	return t->first + ((v - t->first) / t->interval + 1) * t->interval;
}

/* The table (TCS_MAX_TIMERS, protocol.h; slot 0 is ITIMER_REAL, which
 * alarm shares), under tcs_locks[TCS_LOCK_STIMERS] (spin_lock.h). */
extern struct tcs_stimer tcs_stimers[TCS_MAX_TIMERS] TCS_HIDDEN;

/* A copy of slot while it is still incarnation gen (0, else -1: deleted),
 * and the overrun of its latest call. */
int tcs_stimer_copy(int slot, uint32_t gen, struct tcs_stimer *out) TCS_HIDDEN;
void tcs_stimer_set_overrun(int slot, uint32_t gen, int overrun) TCS_HIDDEN;
/* Forgets every signal timer (a new child has none). */
void tcs_timers_forget_all(void) TCS_HIDDEN;
/* The thread a timer's signal signo goes to; 0: the process. */
int tcs_timer_signal_target(int signo) TCS_HIDDEN;

#endif
