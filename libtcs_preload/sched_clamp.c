/* What a controller may have of the real-time priorities and CPU affinity
 * it asks for (sched_clamp.h). The coordinator stops a computing
 * controller from a SCHED_FIFO priority just above the controller's
 * (TCS_CONTROLLER_FIFO_PRIO + 1) on the same core: a thread of the program
 * at a higher one (cyclictest -p 80) would shut it out, and run on
 * unbudgeted. So SCHED_FIFO and SCHED_RR requests are
 * granted at TCS_CONTROLLER_FIFO_PRIO at most, or as SCHED_OTHER where the
 * coordinator itself has no real-time priority; SCHED_DEADLINE, which
 * outranks every priority, is granted as the highest of those (stress-ng
 * --cyclic asks for it first). Requests to run elsewhere than the
 * core tcs gives the controller succeed without moving it: a controller is
 * one virtual CPU. Each is said once. */
#include <pthread.h>
#include <sched.h>

#include "raw_syscall.h"
#include "report.h"
#include "sched_clamp.h"
#include "timer_slack.h"

/* The kernel's struct sched_attr, as far as it matters here. */
struct tcs_sched_attr {
	uint32_t size;
	uint32_t sched_policy;
	uint64_t sched_flags;
	int32_t sched_nice;
	uint32_t sched_priority;
};

/* Where the coordinator has a real-time priority above ours: the highest a
 * controller's thread may have. 0: none. */
static int tcs_rt_ceiling(void)
{
	return (tcs_rt.page->flags & TCS_PAGE_FIFO) ? TCS_CONTROLLER_FIFO_PRIO : 0;
}

void tcs_sched_clamp(int *policy, int *prio)
{
	if (!tcs_rt_policy(*policy))
		return;
	int ceiling = tcs_rt_ceiling();
	if (*prio <= ceiling)
		return;
	static int once;
	tcs_report_once(&once, ceiling ? "a real-time priority above 2 was lowered to 2: the coordinator, at 3, must "
					  "be able to stop the controller"
					: "a real-time priority was asked for and SCHED_OTHER given: the coordinator runs "
					  "without one here");
	if (ceiling) {
		*prio = ceiling;
	} else {
		*policy = SCHED_OTHER | (*policy & SCHED_RESET_ON_FORK);
		*prio = 0;
	}
}

long tcs_sched_setscheduler(long pid, int policy, const struct sched_param *param)
{
	if (!param)
		return -EINVAL;
	struct sched_param p = *param;
	int asked = policy;
	tcs_sched_clamp(&policy, &p.sched_priority);
	long r = tcs_sys3(SYS_sched_setscheduler, pid, policy, &p);
	if (r == 0)
		tcs_policy_set_tid(pid, asked);
	return r;
}

long tcs_sched_setattr(long pid, const void *uattr, long flags)
{
	const struct tcs_sched_attr *a = uattr;
	if (!a || a->size < sizeof *a || a->size > 4096)
		return tcs_sys3(SYS_sched_setattr, pid, uattr, flags); /* the kernel's error */
	unsigned char copy[4096];
	__builtin_memcpy(copy, a, a->size);
	struct tcs_sched_attr *c = (struct tcs_sched_attr *)copy;
	int policy = (int)c->sched_policy, prio = (int)c->sched_priority, asked = policy;
	if (policy == SCHED_DEADLINE) {
		static int once;
		tcs_report_once(&once, "SCHED_DEADLINE granted as SCHED_FIFO below the coordinator: a deadline task "
				       "would outrank it");
		policy = SCHED_FIFO;
		prio = 99;
		c->sched_flags = 0; /* (deadline-only flags) */
	}
	tcs_sched_clamp(&policy, &prio);
	c->sched_policy = (uint32_t)policy;
	c->sched_priority = (uint32_t)prio;
	long r = tcs_sys3(SYS_sched_setattr, pid, copy, flags);
	if (r == 0)
		tcs_policy_set_tid(pid, asked);
	return r;
}

long tcs_sched_setaffinity(size_t size, const cpu_set_t *set)
{
	/* Said when it matters: the set leaves out the core it runs on. */
	int cpu = sched_getcpu();
	if (cpu >= 0 && (size_t)cpu < size * 8 && CPU_ISSET_S((size_t)cpu, size, set))
		return 0;
	static int once;
	tcs_report_once(&once, "CPU affinity requests succeed without moving the controller: it is one virtual CPU "
			       "on the core tcs gives it");
	return 0;
}

/* pthread_create with attributes that ask for an explicit real-time
 * policy: glibc applies them inside, where no hook sees it, so the
 * attributes are clamped for the call (and restored: they are the caller's). */
int tcs_sched_clamp_attr(pthread_attr_t *attr, struct sched_param *saved, int *saved_policy)
{
	int inherit, policy;
	struct sched_param p;
	if (!attr || pthread_attr_getinheritsched(attr, &inherit) != 0 || inherit != PTHREAD_EXPLICIT_SCHED ||
	    pthread_attr_getschedpolicy(attr, &policy) != 0 || pthread_attr_getschedparam(attr, &p) != 0)
		return 0;
	*saved = p;
	*saved_policy = policy;
	int clamped_policy = policy, prio = p.sched_priority;
	tcs_sched_clamp(&clamped_policy, &prio);
	if (clamped_policy == policy && prio == p.sched_priority)
		return 0;
	p.sched_priority = prio;
	pthread_attr_setschedpolicy(attr, clamped_policy);
	pthread_attr_setschedparam(attr, &p);
	return 1;
}

void tcs_sched_restore_attr(pthread_attr_t *attr, const struct sched_param *saved, int saved_policy)
{
	pthread_attr_setschedpolicy(attr, saved_policy);
	pthread_attr_setschedparam(attr, saved);
}
