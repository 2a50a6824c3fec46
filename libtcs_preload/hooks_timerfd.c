/* timerfd_create, timerfd_settime, timerfd_gettime in virtual time.
 *
 * A virtual timerfd is an eventfd: like a timerfd, reading it returns an
 * 8-byte count and resets it, and the kernel reports it readable to poll,
 * select and epoll (epoll sets included, which tcs does not see). tcs keeps
 * the timer's next expiry in virtual time and writes the expirations into
 * the eventfd when the program looks: before a multiplexer checks its fds,
 * and in read(). Multiplexers also wake at the next expiry, so a wait on a
 * timerfd ends at its virtual time. The timers, and a timerfd's read (the
 * read hook calls it through the fd table), are timerfds.c's. */
#include <fcntl.h>
#include <sys/timerfd.h>

#include "raw_syscall.h"
#include "report.h"
#include "spin.h"
#include "timerfds.h"
#include "vclock.h"
#include "wait.h"

static int tcs_timer_clock_ok(clockid_t id)
{
	return id == CLOCK_MONOTONIC || id == CLOCK_REALTIME || id == CLOCK_BOOTTIME || id == CLOCK_REALTIME_ALARM ||
	       id == CLOCK_BOOTTIME_ALARM;
}

TCS_EXPORT int timerfd_create(int clockid, int flags)
{
	if (!tcs_active())
		return tcs_errno_result(tcs_sys2(SYS_timerfd_create, clockid, flags));
	if (!tcs_timer_clock_ok(clockid) || (flags & ~(TFD_NONBLOCK | TFD_CLOEXEC)))
		return tcs_errno_result(-EINVAL);
	/* TFD_NONBLOCK and TFD_CLOEXEC are EFD_NONBLOCK and EFD_CLOEXEC. */
	long fd = tcs_sys2(SYS_eventfd2, 0, flags);
	if (fd < 0)
		return tcs_errno_result(fd);
	if (fd >= TCS_FD_MAX) {
		tcs_sys1(SYS_close, fd);
		return tcs_errno_result(-EMFILE);
	}
	if (tcs_vtimer_add((int)fd, clockid) < 0) {
		tcs_sys1(SYS_close, fd);
		static int once;
		tcs_report_once(&once, "more than 64 timerfds: the 65th is refused (EMFILE)");
		return tcs_errno_result(-EMFILE);
	}
	return (int)fd;
}

TCS_EXPORT int timerfd_gettime(int fd, struct itimerspec *cur)
{
	struct tcs_vtimer *t = tcs_vtimer_of(fd);
	if (!t || !tcs_active())
		return tcs_errno_result(tcs_sys2(SYS_timerfd_gettime, fd, cur));
	int64_t now = tcs_timer_read_vnow();
	tcs_vtimers_fire(now);
	*cur = tcs_vtimer_value(t, now);
	return 0;
}

TCS_EXPORT int timerfd_settime(int fd, int flags, const struct itimerspec *val, struct itimerspec *old)
{
	struct tcs_vtimer *t = tcs_vtimer_of(fd);
	if (!t || !tcs_active())
		return tcs_errno_result(tcs_sys4(SYS_timerfd_settime, fd, flags, val, old));
	if (!val || !tcs_ts_valid(&val->it_value) || !tcs_ts_valid(&val->it_interval) ||
	    (flags & ~(TFD_TIMER_ABSTIME | TFD_TIMER_CANCEL_ON_SET)))
		return tcs_errno_result(-EINVAL);
	int64_t now = tcs_vnow();
	tcs_vtimers_fire(now);
	uint64_t stale;
	tcs_vtimer_drain(fd, &stale); /* arming anew resets the count, as for a timerfd */
	int64_t value = tcs_ts_to_ns(&val->it_value);
	int64_t next = TCS_NEVER;
	if (value > 0)
		next = (flags & TFD_TIMER_ABSTIME) ? value - tcs_sleep_clock_origin(t->clock) : tcs_ns_add(now, value);
	tcs_vtimer_arm(t, next, tcs_ts_to_ns(&val->it_interval), now, old);
	return 0;
}
