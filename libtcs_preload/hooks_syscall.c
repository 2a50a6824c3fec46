/* syscall(): a program (or a library: libstdc++'s futures and atomic waits)
 * calling the kernel by number. Sleeps go to their hooks; futex waits with
 * a timeout park in virtual time (parking.c) and futex wakes also wake the
 * parked; io_uring is refused (its timeouts and waits would run in real
 * time, unseen): programs fall back to plain calls on ENOSYS. Everything
 * else goes to the kernel unchanged (signals to other processes are told to
 * the coordinator, wait.c), clock reads included: syscall(
 * SYS_clock_gettime) is the documented way for a program to read the real
 * clocks of this machine (examples/pendulum_pd.c measures its work so). */
#include <linux/futex.h>
#include <stdarg.h>

#include "parking.h"
#include "random.h"
#include "raw_syscall.h"
#include "report.h"
#include "sched_clamp.h"
#include "timer_slack.h"
#include "vclock.h"
#include "wait.h"

/* A futex wait with a timeout, in virtual time: 0 (woken, or spurious),
 * or -EAGAIN, -ETIMEDOUT, -EINTR. */
static long tcs_futex_wait(const int *uaddr, int op, int val, const struct timespec *timeout)
{
	int cmd = op & FUTEX_CMD_MASK;
	struct tcs_wait_time t = { 0, 0, 0, 0, 0, 0 };
	if (!tcs_ts_valid(timeout))
		return -EINVAL;
	if (cmd == FUTEX_WAIT) {
		/* Relative, on CLOCK_MONOTONIC. */
		t.deadline = tcs_ts_to_ns(timeout);
		t.relative = 1;
	} else {
		int64_t origin = tcs_sleep_clock_origin((op & FUTEX_CLOCK_REALTIME) ? CLOCK_REALTIME : CLOCK_MONOTONIC);
		int64_t at = tcs_ts_to_ns(timeout);
		t.deadline = at > origin ? at - origin : 0;
	}
	int slot = tcs_park_begin(uaddr);
	if (__atomic_load_n(uaddr, __ATOMIC_SEQ_CST) != val) {
		tcs_park_end(slot);
		return -EAGAIN;
	}
	int w = tcs_park_wait(slot, &t, 0);
	tcs_park_end(slot);
	if (w == -EINTR)
		return -EINTR;
	return w == TCS_WAIT_DEADLINE ? -ETIMEDOUT : 0;
}

static long tcs_futex(long a[6])
{
	int op = (int)a[1], cmd = op & FUTEX_CMD_MASK;
	const struct timespec *timeout = (const struct timespec *)a[3];
	if ((cmd == FUTEX_WAIT || cmd == FUTEX_WAIT_BITSET) && timeout && tcs_wait_enter()) {
		long r = tcs_futex_wait((const int *)a[0], op, (int)a[2], timeout);
		tcs_wait_leave();
		return r;
	}
	long r = tcs_sys6(SYS_futex, a[0], a[1], a[2], a[3], a[4], a[5]);
	if ((cmd == FUTEX_WAKE || cmd == FUTEX_WAKE_BITSET) && r >= 0)
		r += tcs_unpark((const void *)a[0]);
	else if (timeout && tcs_active() && (cmd == FUTEX_LOCK_PI || cmd == FUTEX_WAIT_REQUEUE_PI)) {
		static int once;
		tcs_report_once(&once, "a priority-inheritance futex with a timeout waited in real time");
	}
	return r;
}

/* A signal sent by number: the coordinator is told whom it is for, then
 * the kernel sends it, then one to this process is told (wait.c). */
static long tcs_signal_syscall(long nr, const long a[6])
{
	long target = a[0], tid = 0;
	int sig = (int)a[1];
	switch (nr) {
	case SYS_kill:
	case SYS_rt_sigqueueinfo:
		break;
	case SYS_tgkill:
		tid = a[1];
		sig = (int)a[2];
		break;
	default: /* tkill, pidfd_send_signal: the process is not at hand */
		target = -1;
		break;
	}
	tcs_signal_sending(target, sig);
	long r = tcs_sys6(nr, a[0], a[1], a[2], a[3], a[4], a[5]);
	if (r == 0)
		tcs_signal_sent(target, tid, sig);
	return r;
}

/* The C convention of syscall(): -1 and errno on failure. */
static long tcs_syscall_result(long r)
{
	if (r < 0 && r > -4096) {
		errno = (int)-r;
		return -1;
	}
	return r;
}

TCS_EXPORT long syscall(long nr, ...)
{
	long a[6];
	va_list ap;
	va_start(ap, nr);
	for (int i = 0; i < 6; i++)
		a[i] = va_arg(ap, long);
	va_end(ap);
	switch (nr) {
	case SYS_futex:
		return tcs_syscall_result(tcs_futex(a));
	case SYS_nanosleep:
		return nanosleep((const struct timespec *)a[0], (struct timespec *)a[1]);
	case SYS_clock_nanosleep: {
		int r = clock_nanosleep((clockid_t)a[0], (int)a[1], (const struct timespec *)a[2], (struct timespec *)a[3]);
		return tcs_syscall_result(-r);
	}
	case SYS_kill:
	case SYS_tgkill:
	case SYS_tkill:
	case SYS_rt_sigqueueinfo:
	case SYS_pidfd_send_signal:
		return tcs_syscall_result(tcs_signal_syscall(nr, a));
	case SYS_sched_setscheduler:
		if (tcs_active())
			return tcs_syscall_result(tcs_sched_setscheduler(a[0], (int)a[1], (const struct sched_param *)a[2]));
		break;
	case SYS_sched_setattr:
		if (tcs_active())
			return tcs_syscall_result(tcs_sched_setattr(a[0], (const void *)a[1], a[2]));
		break;
	case SYS_prctl:
		return tcs_syscall_result(tcs_prctl((int)a[0], (const unsigned long *)&a[1]));
	case SYS_getrandom:
		return tcs_syscall_result(tcs_getrandom((void *)a[0], (size_t)a[1], (unsigned)a[2]));
	case SYS_sched_setaffinity:
		if (tcs_active())
			return tcs_syscall_result(a[2] ? tcs_sched_setaffinity((size_t)a[1], (const cpu_set_t *)a[2]) : -EFAULT);
		break;
	case SYS_io_uring_setup:
		if (tcs_active()) {
			static int once;
			tcs_report_once(&once, "io_uring refused (ENOSYS): its waits and timeouts cannot run in virtual time");
			return tcs_syscall_result(-ENOSYS);
		}
		break;
	}
	return tcs_syscall_result(tcs_sys6(nr, a[0], a[1], a[2], a[3], a[4], a[5]));
}
