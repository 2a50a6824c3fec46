/* The virtual timerfds' table (timerfds.h). Timers live in a small table
 * shared by the fds that refer to them (dup); each keeps its next expiry
 * in virtual time, and is made readable (its expirations counted into its
 * eventfd) when the program looks: before a multiplexer checks its fds
 * (hooks_poll.c), and in read() (hooks_timerfd.c). */
#include "devices.h"
#include "raw_syscall.h"
#include "spin_lock.h"
#include "timerfds.h"

#define TCS_VTIMERS_MAX 64

static struct tcs_vtimer tcs_vtimers[TCS_VTIMERS_MAX];
static uint8_t tcs_fd_vtimer[TCS_DEVICE_FD_MAX]; /* slot + 1, or 0 */
static int tcs_vtimers_count; /* armed */

struct tcs_vtimer *tcs_vtimer_of(int fd)
{
	if (fd < 0 || fd >= TCS_DEVICE_FD_MAX || !tcs_fd_vtimer[fd])
		return NULL;
	return &tcs_vtimers[tcs_fd_vtimer[fd] - 1];
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

void tcs_vtimer_forget(int fd)
{
	struct tcs_vtimer *t = tcs_vtimer_of(fd);
	if (!t)
		return;
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_TIMERFDS]);
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
	tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
}

void tcs_vtimer_copy(int from, int to)
{
	struct tcs_vtimer *t = tcs_vtimer_of(from);
	if (!t || to < 0 || to >= TCS_DEVICE_FD_MAX)
		return;
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_TIMERFDS]);
	t->refs++;
	tcs_fd_vtimer[to] = tcs_fd_vtimer[from];
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
	tcs_fd_vtimer[fd] = (uint8_t)(slot + 1);
	tcs_unlock(&tcs_locks[TCS_LOCK_TIMERFDS], signals);
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
