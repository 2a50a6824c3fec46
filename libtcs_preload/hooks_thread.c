/* pthread_create: a controller's threads share its core, and are counted
 * in the clock page: from the first one on, the coordinator looks at every
 * thread before it lets virtual time pass. Each thread's channel is made at
 * its first wait (thread_channels.c). */
#include <pthread.h>
#include <sched.h>

#include "raw_syscall.h"
#include "real.h"
#include "sched_clamp.h"
#include "timer_slack.h"

/* tcs runs a controller SCHED_FIFO so that nothing else takes its core while
 * it computes. Its threads, though, must share that core the way the kernel
 * shares one between the threads of an ordinary program: at one FIFO
 * priority a thread woken while another computes would wait until that one
 * blocked. So before its first thread the process steps down to
 * SCHED_OTHER, which new threads inherit; the coordinator stays above it.
 * A policy the program chose itself is left alone. */
static void tcs_threads_share_core(void)
{
	struct sched_param sp;
	if (sched_getscheduler(0) != SCHED_FIFO || sched_getparam(0, &sp) != 0 ||
	    sp.sched_priority != TCS_CONTROLLER_FIFO_PRIO)
		return;
	sp.sched_priority = 0;
	tcs_sys3(SYS_sched_setscheduler, 0, SCHED_OTHER, &sp);
}

TCS_EXPORT int pthread_create(pthread_t *thread, const pthread_attr_t *attr, void *(*start)(void *), void *arg)
{
	if (tcs_active() && __atomic_fetch_add(&tcs_rt.page->threads_started, 1, __ATOMIC_RELAXED) == 0)
		tcs_threads_share_core();
	struct sched_param saved;
	int saved_policy;
	pthread_attr_t *own = (pthread_attr_t *)attr;
	int clamped = tcs_active() && tcs_sched_clamp_attr(own, &saved, &saved_policy);
	/* (Resolved here when a library's constructor, before ours, starts a thread.) */
	int r = tcs_active() ? tcs_create_with_slack(tcs_real()->pthread_create, thread, attr, start, arg)
			     : tcs_real()->pthread_create(thread, attr, start, arg);
	if (clamped)
		tcs_sched_restore_attr(own, &saved, saved_policy);
	/* In lockstep the new thread runs first, till it waits: a spin of
	 * this one (spin.c) would otherwise take virtual time for as long as
	 * the kernel kept it waiting, and its first wait would begin that much
	 * later, by the wall clock's chance. */
	if (r == 0 && tcs_active() && tcs_rt.page->mode == TCS_MODE_LOCKSTEP)
		tcs_sys0(SYS_sched_yield);
	return r;
}
