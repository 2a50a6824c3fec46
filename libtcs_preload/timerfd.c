/* timerfd_create, timerfd_settime, timerfd_gettime in virtual time.
 *
 * A virtual timerfd is an eventfd: like a timerfd, reading it returns an
 * 8-byte count and resets it, and the kernel reports it readable to poll,
 * select and epoll (epoll sets included, which tcs does not see). tcs keeps
 * the timer's next expiry in virtual time and writes the expirations into
 * the eventfd when the program looks: before a multiplexer checks its fds,
 * and in read(). Multiplexers also wake at the next expiry, so a wait on a
 * timerfd ends at its virtual time. Timers live in a small table shared by
 * the fds that refer to them (dup). */
#include <fcntl.h>
#include <sys/timerfd.h>

#include "devices.h"
#include "raw_syscall.h"
#include "report.h"
#include "spin_lock.h"
#include "timerfd.h"
#include "vclock.h"
#include "wait.h"

#define TCS_VTIMERS_MAX 64

struct tcs_vtimer {
	int refs;         /* fds referring to it; 0: a free slot */
	int fd;           /* one of them, to write expirations into */
	clockid_t clock;  /* for absolute times and gettime */
	int64_t next;     /* virtual ns of the next expiry; TCS_NEVER: disarmed */
	int64_t interval; /* 0: one-shot */
};

static struct tcs_vtimer tcs_vtimers[TCS_VTIMERS_MAX];
static uint8_t tcs_fd_vtimer[TCS_DEVICE_FD_MAX]; /* slot + 1, or 0 */
static int tcs_vtimer_lock;
static int tcs_vtimers_count; /* armed */

static struct tcs_vtimer *tcs_slot(int fd)
{
	if (fd < 0 || fd >= TCS_DEVICE_FD_MAX || !tcs_fd_vtimer[fd])
		return NULL;
	return &tcs_vtimers[tcs_fd_vtimer[fd] - 1];
}

int tcs_vtimer_of(int fd)
{
	return tcs_slot(fd) != NULL;
}

int tcs_vtimers_armed(void)
{
	return __atomic_load_n(&tcs_vtimers_count, __ATOMIC_RELAXED) > 0;
}

static void tcs_set_next(struct tcs_vtimer *t, int64_t next)
{
	if ((t->next == TCS_NEVER) != (next == TCS_NEVER))
		__atomic_add_fetch(&tcs_vtimers_count, next == TCS_NEVER ? -1 : 1, __ATOMIC_RELAXED);
	t->next = next;
}

int64_t tcs_vtimers_fire(int64_t v)
{
	int64_t soonest = TCS_NEVER;
	if (!tcs_vtimers_armed())
		return soonest;
	tcs_spin_lock(&tcs_vtimer_lock);
	for (int i = 0; i < TCS_VTIMERS_MAX; i++) {
		struct tcs_vtimer *t = &tcs_vtimers[i];
		if (!t->refs || t->next == TCS_NEVER)
			continue;
		if (t->next <= v) {
			uint64_t n = 1;
			if (t->interval > 0)
				n += (uint64_t)((v - t->next) / t->interval);
			tcs_sys3(SYS_write, t->fd, &n, sizeof n);
			tcs_set_next(t, t->interval > 0 ? t->next + (int64_t)n * t->interval : TCS_NEVER);
		}
		if (t->next < soonest)
			soonest = t->next;
	}
	tcs_spin_unlock(&tcs_vtimer_lock);
	return soonest;
}

/* Reads the eventfd's count without blocking: 8, or -EAGAIN. */
static long tcs_drain(int fd, void *buf)
{
	struct pollfd p = { fd, POLLIN, 0 };
	struct timespec zero = { 0, 0 };
	long r = tcs_sys5(SYS_ppoll, &p, 1, &zero, NULL, TCS_KERNEL_SIGSET_SIZE);
	if (r < 0)
		return r;
	if (r == 0)
		return -EAGAIN;
	return tcs_sys3(SYS_read, fd, buf, 8);
}

long tcs_vtimer_read(int fd, void *buf, size_t n)
{
	if (n < 8)
		return -EINVAL;
	struct tcs_vtimer *t = tcs_slot(fd);
	for (;;) {
		tcs_vtimers_fire(tcs_vnow());
		long r = tcs_drain(fd, buf);
		if (r != -EAGAIN)
			return r;
		long fl = tcs_sys3(SYS_fcntl, fd, F_GETFL, 0);
		if (fl < 0)
			return fl;
		if (fl & O_NONBLOCK)
			return -EAGAIN;
		/* Blocks until the next expiry, in virtual time (forever when
		 * disarmed, as a real timerfd's read does). */
		if (!tcs_wait_enter())
			return tcs_sys3(SYS_read, fd, buf, 8);
		struct tcs_wait_time w = { t->next, 0, 0, 0, 0 };
		int got = tcs_wait(&w, TCS_BLOCK_SLEEP, TCS_BLOCK_ABSOLUTE, NULL, 0, NULL);
		tcs_wait_leave();
		if (got == -EINTR)
			return -EINTR;
	}
}

void tcs_vtimer_forget(int fd)
{
	struct tcs_vtimer *t = tcs_slot(fd);
	if (!t)
		return;
	tcs_spin_lock(&tcs_vtimer_lock);
	tcs_fd_vtimer[fd] = 0;
	if (--t->refs == 0) {
		tcs_set_next(t, TCS_NEVER);
	} else if (t->fd == fd) {
		for (int i = 0; i < TCS_DEVICE_FD_MAX; i++)
			if (tcs_fd_vtimer[i] && &tcs_vtimers[tcs_fd_vtimer[i] - 1] == t) {
				t->fd = i;
				break;
			}
	}
	tcs_spin_unlock(&tcs_vtimer_lock);
}

void tcs_vtimer_copy(int from, int to)
{
	struct tcs_vtimer *t = tcs_slot(from);
	if (!t || to < 0 || to >= TCS_DEVICE_FD_MAX)
		return;
	tcs_spin_lock(&tcs_vtimer_lock);
	t->refs++;
	tcs_fd_vtimer[to] = tcs_fd_vtimer[from];
	tcs_spin_unlock(&tcs_vtimer_lock);
}

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
	if (fd >= TCS_DEVICE_FD_MAX) {
		tcs_sys1(SYS_close, fd);
		return tcs_errno_result(-EMFILE);
	}
	tcs_spin_lock(&tcs_vtimer_lock);
	int slot = -1;
	for (int i = 0; i < TCS_VTIMERS_MAX && slot < 0; i++)
		if (!tcs_vtimers[i].refs)
			slot = i;
	if (slot < 0) {
		tcs_spin_unlock(&tcs_vtimer_lock);
		tcs_sys1(SYS_close, fd);
		static int once;
		tcs_report_once(&once, "more than 64 timerfds: the 65th is refused (EMFILE)");
		return tcs_errno_result(-EMFILE);
	}
	tcs_vtimers[slot] = (struct tcs_vtimer){ 1, (int)fd, clockid, TCS_NEVER, 0 };
	tcs_fd_vtimer[fd] = (uint8_t)(slot + 1);
	tcs_spin_unlock(&tcs_vtimer_lock);
	return (int)fd;
}

static struct itimerspec tcs_timer_value(const struct tcs_vtimer *t, int64_t now)
{
	struct itimerspec v = { 0 };
	if (t->next != TCS_NEVER)
		v.it_value = tcs_ns_to_ts(t->next > now ? t->next - now : 1);
	v.it_interval = tcs_ns_to_ts(t->interval);
	return v;
}

TCS_EXPORT int timerfd_gettime(int fd, struct itimerspec *cur)
{
	struct tcs_vtimer *t = tcs_slot(fd);
	if (!t || !tcs_active())
		return tcs_errno_result(tcs_sys2(SYS_timerfd_gettime, fd, cur));
	int64_t now = tcs_vnow();
	tcs_vtimers_fire(now);
	tcs_spin_lock(&tcs_vtimer_lock);
	*cur = tcs_timer_value(t, now);
	tcs_spin_unlock(&tcs_vtimer_lock);
	return 0;
}

TCS_EXPORT int timerfd_settime(int fd, int flags, const struct itimerspec *val, struct itimerspec *old)
{
	struct tcs_vtimer *t = tcs_slot(fd);
	if (!t || !tcs_active())
		return tcs_errno_result(tcs_sys4(SYS_timerfd_settime, fd, flags, val, old));
	if (!val || !tcs_ts_valid(&val->it_value) || !tcs_ts_valid(&val->it_interval) ||
	    (flags & ~(TFD_TIMER_ABSTIME | TFD_TIMER_CANCEL_ON_SET)))
		return tcs_errno_result(-EINVAL);
	int64_t now = tcs_vnow();
	tcs_vtimers_fire(now);
	uint64_t stale;
	tcs_drain(fd, &stale); /* arming anew resets the count, as for a timerfd */
	int64_t value = tcs_ts_to_ns(&val->it_value);
	int64_t next = TCS_NEVER;
	if (value > 0)
		next = (flags & TFD_TIMER_ABSTIME) ? value - tcs_sleep_clock_origin(t->clock) : tcs_ns_add(now, value);
	tcs_spin_lock(&tcs_vtimer_lock);
	if (old)
		*old = tcs_timer_value(t, now);
	t->interval = next == TCS_NEVER ? 0 : tcs_ts_to_ns(&val->it_interval);
	tcs_set_next(t, next);
	tcs_spin_unlock(&tcs_vtimer_lock);
	return 0;
}
