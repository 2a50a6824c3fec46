/* Timer slack per thread (timer_slack.h), kept as Linux keeps it: a new
 * thread starts with its creator's slack (and goes back to that with
 * PR_SET_TIMERSLACK 0), a fork's child with its parent's; a real-time
 * thread has none. (After exec a program starts again at 50 us: the
 * kernel keeps the value across exec, this library does not.) */
#include "timer_slack.h"

#include <sched.h>
#include <sys/prctl.h>

#include "raw_syscall.h"
#include "spin_lock.h"

/* Linux's slack for a normal thread (init's, inherited by everything). */
#define TCS_DEFAULT_SLACK_NS 50000
/* The most a select or poll timeout adds of its own (MAX_SLACK). */
#define TCS_MAX_POLL_SLACK_NS (100 * TCS_NS_PER_MS)

/* 0 in each: not set, the defaults. */
static __thread int64_t tcs_slack_ns;    /* what PR_SET_TIMERSLACK set */
static __thread int64_t tcs_slack_start; /* what the thread started with */
static __thread int tcs_rt_thread;       /* 1: real-time, -1: not (set by the program) */

/* A real-time policy as Linux's timer slack sees it: a deadline task's too. */
static int tcs_rt_thread_policy(int policy)
{
	return tcs_rt_policy(policy) || (policy & ~SCHED_RESET_ON_FORK) == SCHED_DEADLINE;
}

/* ---- policies set for other threads, found by them at their next wait ---- */

#define TCS_POLICY_NOTES 16
static struct {
	long tid;         /* or 0 */
	pthread_t thread; /* (tid 0) */
	int rt;           /* 0: free; 1 real-time; -1 not */
} tcs_notes[TCS_POLICY_NOTES];
static int tcs_notes_pending;

static void tcs_note(long tid, pthread_t thread, int policy)
{
	int rt = tcs_rt_thread_policy(policy) ? 1 : -1;
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_SLACK_NOTES]);
	int free_slot = -1;
	for (int i = 0; i < TCS_POLICY_NOTES; i++) {
		if (tcs_notes[i].rt == 0) {
			if (free_slot < 0)
				free_slot = i;
		} else if (tid ? tcs_notes[i].tid == tid : !tcs_notes[i].tid && pthread_equal(tcs_notes[i].thread, thread)) {
			tcs_notes[i].rt = rt; /* the later setting stands */
			free_slot = -2;
			break;
		}
	}
	if (free_slot >= 0) { /* (full: that thread keeps what it had) */
		tcs_notes[free_slot].tid = tid;
		tcs_notes[free_slot].thread = thread;
		tcs_notes[free_slot].rt = rt;
		__atomic_add_fetch(&tcs_notes_pending, 1, __ATOMIC_RELEASE);
	}
	tcs_unlock(&tcs_locks[TCS_LOCK_SLACK_NOTES], signals);
}

static void tcs_take_notes(void)
{
	if (__atomic_load_n(&tcs_notes_pending, __ATOMIC_ACQUIRE) == 0)
		return;
	long tid = tcs_sys0(SYS_gettid);
	pthread_t self = pthread_self();
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_SLACK_NOTES]);
	for (int i = 0; i < TCS_POLICY_NOTES; i++) {
		if (tcs_notes[i].rt == 0 ||
		    !(tcs_notes[i].tid ? tcs_notes[i].tid == tid : pthread_equal(tcs_notes[i].thread, self)))
			continue;
		tcs_rt_thread = tcs_notes[i].rt;
		tcs_notes[i].rt = 0;
		__atomic_sub_fetch(&tcs_notes_pending, 1, __ATOMIC_RELEASE);
	}
	tcs_unlock(&tcs_locks[TCS_LOCK_SLACK_NOTES], signals);
}

void tcs_policy_set_self(int policy)
{
	tcs_rt_thread = tcs_rt_thread_policy(policy) ? 1 : -1;
}

void tcs_policy_set_tid(long tid, int policy)
{
	if (tid == 0 || tid == tcs_sys0(SYS_gettid))
		tcs_policy_set_self(policy);
	else
		tcs_note(tid, (pthread_t)0, policy);
}

void tcs_policy_set_thread(pthread_t thread, int policy)
{
	if (pthread_equal(thread, pthread_self()))
		tcs_policy_set_self(policy);
	else
		tcs_note(0, thread, policy);
}

/* ---- the slack ---- */

static int64_t tcs_slack_of_thread(void)
{
	if (tcs_slack_ns > 0)
		return tcs_slack_ns;
	return tcs_slack_start > 0 ? tcs_slack_start : TCS_DEFAULT_SLACK_NS;
}

int64_t tcs_timer_slack(void)
{
	tcs_take_notes();
	return tcs_rt_thread > 0 ? 0 : tcs_slack_of_thread();
}

int64_t tcs_poll_slack(int64_t timeout_ns)
{
	int64_t slack = tcs_timer_slack();
	if (slack == 0 || timeout_ns <= 0)
		return slack;
	int64_t own = timeout_ns / 1000;
	if (own > TCS_MAX_POLL_SLACK_NS)
		own = TCS_MAX_POLL_SLACK_NS;
	return own > slack ? own : slack;
}

long tcs_prctl(int option, const unsigned long a[4])
{
	if (tcs_active() && option == PR_SET_TIMERSLACK) {
		/* (0 goes back to the slack the thread started with, as in Linux.) */
		tcs_slack_ns = a[0] > (unsigned long)INT64_MAX ? INT64_MAX : (int64_t)a[0];
		return 0;
	}
	if (tcs_active() && option == PR_GET_TIMERSLACK)
		return (long)tcs_slack_of_thread();
	return tcs_sys5(SYS_prctl, option, a[0], a[1], a[2], a[3]);
}

/* ---- new threads ---- */

/* What a new thread takes from its creator: slots claimed by the creator,
 * released by the thread as it starts (no malloc in this library). */
#define TCS_STARTS 32
static struct tcs_start {
	int used;
	void *(*start)(void *);
	void *arg;
	int64_t slack;
	int rt;
} tcs_starts[TCS_STARTS];

static void *tcs_thread_begins(void *p)
{
	struct tcs_start *s = p;
	void *(*start)(void *) = s->start;
	void *arg = s->arg;
	tcs_slack_start = s->slack;
	tcs_rt_thread = s->rt;
	__atomic_store_n(&s->used, 0, __ATOMIC_RELEASE);
	return start(arg);
}

/* Whether attr, as asked, makes the new thread real-time (1), not (-1),
 * or leaves it to inherit its creator's policy (0). */
static int tcs_attr_rt(const pthread_attr_t *attr)
{
	int inherit, policy;
	if (!attr || pthread_attr_getinheritsched(attr, &inherit) != 0 || inherit != PTHREAD_EXPLICIT_SCHED ||
	    pthread_attr_getschedpolicy(attr, &policy) != 0)
		return 0;
	return tcs_rt_thread_policy(policy) ? 1 : -1;
}

int tcs_create_with_slack(int (*real)(pthread_t *, const pthread_attr_t *, void *(*)(void *), void *),
			  pthread_t *thread, const pthread_attr_t *attr, void *(*start)(void *), void *arg)
{
	tcs_take_notes();
	int rt = tcs_attr_rt(attr);
	if (rt == 0)
		rt = tcs_rt_thread;
	int64_t slack = tcs_slack_of_thread();
	if (rt <= 0 && slack == TCS_DEFAULT_SLACK_NS)
		return real(thread, attr, start, arg); /* a new thread's defaults */
	for (int i = 0; i < TCS_STARTS; i++) {
		struct tcs_start *s = &tcs_starts[i];
		int expected = 0;
		if (!__atomic_compare_exchange_n(&s->used, &expected, 1, 0, __ATOMIC_ACQUIRE, __ATOMIC_RELAXED))
			continue;
		s->start = start;
		s->arg = arg;
		s->slack = slack;
		s->rt = rt;
		int r = real(thread, attr, tcs_thread_begins, s);
		if (r != 0)
			__atomic_store_n(&s->used, 0, __ATOMIC_RELEASE);
		return r;
	}
	return real(thread, attr, start, arg); /* (32 starting at once: defaults) */
}
