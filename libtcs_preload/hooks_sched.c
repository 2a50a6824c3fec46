/* Priority, affinity and timer slack hooks: sched_setscheduler,
 * sched_setparam, sched_setaffinity, pthread_setaffinity_np,
 * pthread_setschedparam, pthread_setschedprio, prctl (sched_setattr comes
 * by number, hooks_syscall.c). What a controller may have of them is
 * sched_clamp.c's to say; its timer slack is timer_slack.c's. */
#include <pthread.h>
#include <sched.h>
#include <stdarg.h>
#include <sys/prctl.h>

#include "raw_syscall.h"
#include "real.h"
#include "sched_clamp.h"
#include "timer_slack.h"

TCS_EXPORT int sched_setscheduler(pid_t pid, int policy, const struct sched_param *param)
{
	if (!tcs_active())
		return tcs_errno_result(tcs_sys3(SYS_sched_setscheduler, pid, policy, param));
	return tcs_errno_result(tcs_sched_setscheduler(pid, policy, param));
}

TCS_EXPORT int sched_setparam(pid_t pid, const struct sched_param *param)
{
	if (!tcs_active() || !param)
		return tcs_errno_result(tcs_sys2(SYS_sched_setparam, pid, param));
	int current = (int)tcs_sys1(SYS_sched_getscheduler, pid);
	if (current < 0)
		return tcs_errno_result(current);
	int policy = current;
	struct sched_param p = *param;
	tcs_sched_clamp(&policy, &p.sched_priority);
	if (policy != current) /* real-time refused here: SCHED_OTHER */
		return tcs_errno_result(tcs_sys3(SYS_sched_setscheduler, pid, policy, &p));
	return tcs_errno_result(tcs_sys2(SYS_sched_setparam, pid, &p));
}

TCS_EXPORT int sched_setaffinity(pid_t pid, size_t size, const cpu_set_t *set)
{
	if (!tcs_active())
		return tcs_errno_result(tcs_sys3(SYS_sched_setaffinity, pid, size, set));
	return tcs_errno_result(tcs_sched_setaffinity(size, set));
}

TCS_EXPORT int pthread_setaffinity_np(pthread_t thread, size_t size, const cpu_set_t *set)
{
	(void)thread;
	if (!tcs_active()) {
		int (*real)(pthread_t, size_t, const cpu_set_t *) = tcs_real()->pthread_setaffinity_np;
		return real ? real(thread, size, set) : ENOSYS;
	}
	return (int)-tcs_sched_setaffinity(size, set);
}

TCS_EXPORT int pthread_setschedparam(pthread_t thread, int policy, const struct sched_param *param)
{
	int (*real)(pthread_t, int, const struct sched_param *) = tcs_real()->pthread_setschedparam;
	if (!real)
		return ENOSYS;
	if (!tcs_active())
		return real(thread, policy, param);
	struct sched_param p = *param;
	int asked = policy;
	tcs_sched_clamp(&policy, &p.sched_priority);
	int r = real(thread, policy, &p);
	if (r == 0)
		tcs_policy_set_thread(thread, asked);
	return r;
}

TCS_EXPORT int pthread_setschedprio(pthread_t thread, int prio)
{
	int (*real)(pthread_t, int) = tcs_real()->pthread_setschedprio;
	if (!real)
		return ENOSYS;
	if (!tcs_active())
		return real(thread, prio);
	int policy, clamped;
	struct sched_param cur;
	int r = pthread_getschedparam(thread, &policy, &cur);
	if (r != 0)
		return r;
	clamped = policy;
	tcs_sched_clamp(&clamped, &prio);
	if (clamped != policy) { /* real-time refused here: SCHED_OTHER */
		cur.sched_priority = prio;
		return pthread_setschedparam(thread, clamped, &cur);
	}
	return real(thread, prio);
}

TCS_EXPORT int prctl(int option, ...)
{
	unsigned long a[4];
	va_list ap;
	va_start(ap, option);
	for (int i = 0; i < 4; i++)
		a[i] = va_arg(ap, unsigned long);
	va_end(ap);
	return tcs_errno_result(tcs_prctl(option, a));
}
