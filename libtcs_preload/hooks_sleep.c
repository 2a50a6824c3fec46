/* Sleep hooks: nanosleep, clock_nanosleep (relative and TIMER_ABSTIME),
 * usleep, sleep, thrd_sleep. A sleep is a wait for a virtual deadline; a
 * signal handler that interrupts it gets EINTR and the virtual time left,
 * exactly as POSIX says, while the coordinator's own SIGSTOP/SIGCONT never
 * shows (the channel read is restarted by the kernel, not interrupted). */
#include <threads.h>

#include "raw_syscall.h"
#include "report.h"
#include "timer_slack.h"
#include "vclock.h"
#include "wait.h"

/* The virtual half of clock_nanosleep; returns 0 or -errno. */
static long tcs_virtual_sleep(clockid_t clock, int flags, const struct timespec *req, struct timespec *rem)
{
	if (!tcs_ts_valid(req))
		return -EINVAL;
	int64_t origin = tcs_sleep_clock_origin(clock);
	if (origin < 0)
		return origin;
	struct tcs_wait_time t = { tcs_ts_to_ns(req), !(flags & TIMER_ABSTIME), 0, 0, 0, tcs_timer_slack() };
	struct tcs_wait_hold held = { 0, 0 };
	if (flags & TIMER_ABSTIME)
		t.deadline = t.deadline > origin ? t.deadline - origin : 0;
	unsigned bflags = (flags & TIMER_ABSTIME) ? TCS_BLOCK_ABSOLUTE : 0;
	long r = tcs_wait_held(&t, &held, TCS_BLOCK_SLEEP, bflags);
	int64_t start = t.start;
	/* Woken to re-check (a signal from another process is on its way, or
	 * one came that no handler took): sleep on to the same deadline, now
	 * absolute. Signals stay blocked from the re-check's answer on and
	 * are let in by each wait's own look and ppoll, as sigsuspend's are:
	 * inside the program's sleep, a handler ends it (EINTR), wherever it
	 * comes; let in before the wait was asked again, through the
	 * mailbox's spin, it went unnoticed and the sleep ran to its end. */
	while (r == TCS_WAIT_RECHECK)
		r = tcs_wait_held(&t, &held, TCS_BLOCK_SLEEP, bflags);
	tcs_wait_unhold(&held);
	t.start = start;
	if (r != -EINTR)
		return 0;
	if (rem && !(flags & TIMER_ABSTIME)) {
		/* req - slept, in timespec arithmetic: exact even for requests
		 * beyond what int64 nanoseconds can hold. */
		struct timespec slept = tcs_ns_to_ts(t.end - t.start);
		rem->tv_sec = req->tv_sec - slept.tv_sec;
		rem->tv_nsec = req->tv_nsec - slept.tv_nsec;
		if (rem->tv_nsec < 0) {
			rem->tv_sec--;
			rem->tv_nsec += TCS_NS_PER_S;
		}
		if (rem->tv_sec < 0)
			rem->tv_sec = rem->tv_nsec = 0;
	}
	return -EINTR;
}

/* Every sleep hook comes here; returns 0 or -errno. */
static long tcs_sleep(clockid_t clock, int flags, const struct timespec *req, struct timespec *rem)
{
	if (!req)
		return -EFAULT;
	if (clock == CLOCK_PROCESS_CPUTIME_ID || clock == CLOCK_THREAD_CPUTIME_ID || clock < 0 ||
	    !tcs_wait_enter()) {
		if (tcs_active() && (clock == CLOCK_PROCESS_CPUTIME_ID || clock < 0)) {
			static int once;
			tcs_report_once(&once, "clock_nanosleep on a CPU-time clock runs in real time");
		}
		return tcs_sys4(SYS_clock_nanosleep, clock, flags, req, rem);
	}
	long r = tcs_virtual_sleep(clock, flags, req, rem);
	tcs_wait_leave();
	return r;
}

TCS_EXPORT int clock_nanosleep(clockid_t clock, int flags, const struct timespec *req, struct timespec *rem)
{
	return (int)-tcs_sleep(clock, flags, req, rem);
}

TCS_EXPORT int nanosleep(const struct timespec *req, struct timespec *rem)
{
	return tcs_errno_result(tcs_sleep(CLOCK_MONOTONIC, 0, req, rem));
}

/* glibc's internal name, which some programs call (no public header). */
TCS_EXPORT int __nanosleep(const struct timespec *req, struct timespec *rem);
TCS_EXPORT int __nanosleep(const struct timespec *req, struct timespec *rem)
{
	return nanosleep(req, rem);
}

TCS_EXPORT int usleep(useconds_t us)
{
	struct timespec req = tcs_ns_to_ts((int64_t)us * TCS_NS_PER_US);
	return tcs_errno_result(tcs_sleep(CLOCK_MONOTONIC, 0, &req, NULL));
}

TCS_EXPORT unsigned int sleep(unsigned int seconds)
{
	struct timespec req = { .tv_sec = seconds, .tv_nsec = 0 }, rem = { 0, 0 };
	if (tcs_sleep(CLOCK_MONOTONIC, 0, &req, &rem) == 0)
		return 0;
	/* As glibc: the unslept time, rounded to the nearest second. */
	return (unsigned int)(rem.tv_sec + (rem.tv_nsec >= 500000000L));
}

TCS_EXPORT int thrd_sleep(const struct timespec *req, struct timespec *rem)
{
	long r = tcs_sleep(CLOCK_REALTIME, 0, req, rem);
	return r == 0 ? 0 : r == -EINTR ? -1 : -2;
}

/* ---- waits for a signal --------------------------------------------------- */

/* pause and sigsuspend: a wait with no deadline that a signal handler ends
 * (a signal delivered in virtual time by a timer, or a real one). mask:
 * the mask during the wait (NULL: the current one). */
static int tcs_wait_for_handler(const sigset_t *mask)
{
	if (!tcs_wait_enter()) {
		long r = mask ? tcs_sys2(SYS_rt_sigsuspend, mask, TCS_KERNEL_SIGSET_SIZE) : tcs_sys0(SYS_pause);
		return tcs_errno_result(r);
	}
	struct tcs_wait_time t = { TCS_NEVER, 0, 0, 0, 0, 0 };
	long r;
	do
		r = tcs_wait(&t, TCS_BLOCK_SLEEP, 0, NULL, 0, mask);
	while (r != -EINTR);
	tcs_wait_leave();
	return tcs_errno_result(-EINTR);
}

TCS_EXPORT int pause(void)
{
	return tcs_active() ? tcs_wait_for_handler(NULL) : tcs_errno_result(tcs_sys0(SYS_pause));
}

TCS_EXPORT int sigsuspend(const sigset_t *mask)
{
	if (!tcs_active())
		return tcs_errno_result(tcs_sys2(SYS_rt_sigsuspend, mask, TCS_KERNEL_SIGSET_SIZE));
	return tcs_wait_for_handler(mask);
}
