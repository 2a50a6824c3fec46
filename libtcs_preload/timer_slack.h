/* Timer slack (timer_slack.c): how long after its deadline a thread's timed
 * wait ends when nothing ends it sooner, as Linux decides it for the thread
 * natively. What the program set (prctl, real-time policies) is kept here,
 * per thread: the kernel's own value cannot say it, since tcs runs the
 * controller SCHED_FIFO itself and the kernel gives real-time threads none. */
#ifndef TCS_PRELOAD_TIMER_SLACK_H
#define TCS_PRELOAD_TIMER_SLACK_H

#include <pthread.h>
#include <sched.h>
#include <stdint.h>

#include "runtime.h"

#ifndef SCHED_DEADLINE
#define SCHED_DEADLINE 6
#endif

/* Whether policy (SCHED_RESET_ON_FORK aside) is SCHED_FIFO or SCHED_RR:
 * what both the slack (none for such a thread) and the clamping of
 * priorities (sched_clamp.c, above this file) ask of a policy. */
static inline int tcs_rt_policy(int policy)
{
	policy &= ~SCHED_RESET_ON_FORK;
	return policy == SCHED_FIFO || policy == SCHED_RR;
}

/* A sleep's or a timed wait's (nanosleep, futex, sigtimedwait): 0 for a
 * thread the program made real-time, else its PR_SET_TIMERSLACK value (what
 * it started with, 50 us by default, unless set). */
int64_t tcs_timer_slack(void) TCS_HIDDEN;
/* A select, poll or epoll wait's of timeout_ns: the larger of the timer
 * slack and 0.1 % of the timeout, at most 100 ms (the kernel's
 * select_estimate_accuracy); 0 for a real-time thread. */
int64_t tcs_poll_slack(int64_t timeout_ns) TCS_HIDDEN;

/* prctl(option, a[0..3]): PR_SET_TIMERSLACK and PR_GET_TIMERSLACK of the
 * calling thread answered here (0, and the slack in ns), the rest by the
 * kernel. 0, a value, or -errno. */
long tcs_prctl(int option, const unsigned long a[4]) TCS_HIDDEN;

/* The program set a scheduling policy (SCHED_*, as asked, before any
 * clamping): for the calling thread (self), for thread `tid`, or for
 * pthread `thread` (the two others found at their next wait). */
void tcs_policy_set_self(int policy) TCS_HIDDEN;
void tcs_policy_set_tid(long tid, int policy) TCS_HIDDEN;
void tcs_policy_set_thread(pthread_t thread, int policy) TCS_HIDDEN;

/* pthread_create: the new thread starts with its creator's slack, and
 * real-time if attr makes it so (explicitly, or inherited from a real-time
 * creator). Either calls real(thread, attr, start, arg) with a start that
 * sets that up first, or, where there is nothing to pass on, as it is. */
int tcs_create_with_slack(int (*real)(pthread_t *, const pthread_attr_t *, void *(*)(void *), void *),
			  pthread_t *thread, const pthread_attr_t *attr, void *(*start)(void *),
			  void *arg) TCS_HIDDEN;

#endif
