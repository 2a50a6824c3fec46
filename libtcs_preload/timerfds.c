/* The virtual timerfds' table (timerfds.h). Timers live in a small table
 * shared by the fds that refer to them (dup), each fd's entry in the fd
 * table naming its slot; each keeps its next expiry in virtual time, and
 * is made readable (its expirations counted into its eventfd) when the
 * program looks: before a multiplexer checks its fds (hooks_poll.c), and
 * in read() (here: the kind's read). The table is changed under its
 * tcs_lock, which blocks every signal while held. */
#include "timerfds.h"

#include <fcntl.h>

#include "raw_syscall.h"
#include "spin_lock.h"
#include "vclock.h"
#include "wait.h"

#define TCS_VTIMERS_MAX 64

static struct tcs_vtimer tcs_vtimers[TCS_VTIMERS_MAX];
static int tcs_vtimers_count; /* armed */

struct tcs_vtimer *tcs_vtimer_of(int fd)
{
	struct tcs_fd e;
	if (!tcs_fd_of(fd, &e) || e.ops != &tcs_timerfd_ops)
		return NULL;
	return &tcs_vtimers[e.slot % TCS_VTIMERS_MAX];
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
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_TIMERFDS]);
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
	tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
	return soonest;
}

/* The kind's forget: fd's entry is gone from the fd table already. */
static void tcs_vtimer_forget(int fd, const struct tcs_fd *e)
{
	struct tcs_vtimer *t = &tcs_vtimers[e->slot % TCS_VTIMERS_MAX];
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_TIMERFDS]);
	if (--t->refs == 0) {
		tcs_set_next(t, TCS_NEVER);
	} else if (t->fd == fd) {
		int other = tcs_fd_find(&tcs_timerfd_ops, e->slot);
		if (other >= 0)
			t->fd = other;
	}
	tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
}

/* The kind's copy: one more fd refers to the timer. */
static void tcs_vtimer_copy(int to, const struct tcs_fd *e)
{
	(void)to;
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_TIMERFDS]);
	tcs_vtimers[e->slot % TCS_VTIMERS_MAX].refs++;
	tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
}

int tcs_vtimer_add(int fd, clockid_t clock)
{
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_TIMERFDS]);
	int slot = -1;
	for (int i = 0; i < TCS_VTIMERS_MAX && slot < 0; i++)
		if (!tcs_vtimers[i].refs)
			slot = i;
	if (slot < 0) {
		tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
		return -EMFILE;
	}
	tcs_vtimers[slot] = (struct tcs_vtimer){ 1, fd, clock, TCS_NEVER, 0 };
	tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
	struct tcs_fd e = { &tcs_timerfd_ops, -1, 0, (unsigned)slot, 0 };
	tcs_fd_set(fd, &e);
	return 0;
}

static struct itimerspec tcs_value(const struct tcs_vtimer *t, int64_t now)
{
	struct itimerspec v = { 0 };
	if (t->next != TCS_NEVER)
		v.it_value = tcs_ns_to_ts(t->next > now ? t->next - now : 1);
	v.it_interval = tcs_ns_to_ts(t->interval);
	return v;
}

struct itimerspec tcs_vtimer_value(const struct tcs_vtimer *t, int64_t now)
{
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_TIMERFDS]);
	struct itimerspec v = tcs_value(t, now);
	tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
	return v;
}

void tcs_vtimer_arm(struct tcs_vtimer *t, int64_t next, int64_t interval, int64_t now, struct itimerspec *old)
{
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_TIMERFDS]);
	if (old)
		*old = tcs_value(t, now);
	t->interval = next == TCS_NEVER ? 0 : interval;
	tcs_set_next(t, next);
	tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
}

long tcs_vtimer_drain(int fd, void *buf)
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

/* read(2) of a timerfd: the expiration count, waiting for the next expiry
 * in virtual time when there is none yet (forever when disarmed, as a real
 * timerfd's read does). */
static long tcs_vtimer_read(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	if (n < 8)
		return -EINVAL;
	struct tcs_vtimer *t = &tcs_vtimers[e->slot % TCS_VTIMERS_MAX];
	for (;;) {
		tcs_vtimers_fire(tcs_vnow());
		long r = tcs_vtimer_drain(fd, buf);
		if (r != -EAGAIN)
			return r;
		long fl = tcs_sys3(SYS_fcntl, fd, F_GETFL, 0);
		if (fl < 0)
			return fl;
		if (fl & O_NONBLOCK)
			return -EAGAIN;
		if (!tcs_wait_enter())
			return tcs_sys3(SYS_read, fd, buf, 8);
		struct tcs_wait_time w = { t->next, 0, 0, 0, 0, 0 };
		int got = tcs_wait(&w, TCS_BLOCK_SLEEP, TCS_BLOCK_ABSOLUTE, NULL, 0, NULL);
		tcs_wait_leave();
		if (got == -EINTR)
			return -EINTR;
	}
}

/* A timerfd is an eventfd to the kernel: its readv, write, poll and epoll
 * are the kernel's; fork keeps it, as the kernel keeps a timerfd. */
const struct tcs_fd_ops tcs_timerfd_ops = {
	.kind = TCS_FD_TIMERFD,
	.read = tcs_vtimer_read,
	.forget = tcs_vtimer_forget,
	.copy = tcs_vtimer_copy,
};
