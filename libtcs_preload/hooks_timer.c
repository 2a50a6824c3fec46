/* Signal timers in virtual time: alarm, setitimer/getitimer (ITIMER_REAL),
 * timer_create (SIGEV_SIGNAL, SIGEV_THREAD_ID, SIGEV_NONE), timer_settime,
 * timer_gettime, timer_getoverrun, timer_delete.
 *
 * The runtime keeps each timer's first expiry and interval in virtual time
 * (slot 0 is ITIMER_REAL, which alarm shares, as in the kernel) and tells
 * the coordinator, which sends the signal when the controller's virtual time
 * reaches an expiry: it stops a computing controller there, and ends a wait
 * (the wait returns EINTR if a handler ran). What is left of a timer is
 * computed here from the same two numbers (kept in signal_timers.c's
 * table). SIGEV_THREAD timers are served by a helper thread each
 * (timer_thread.c). */
#include <signal.h>
#include <sys/time.h>

#include "raw_syscall.h"
#include "real.h"
#include "roundtrip.h"
#include "signal_timers.h"
#include "spin.h"
#include "spin_lock.h"
#include "timer_thread.h"
#include "vclock.h"
#include "wait.h"

/* Our timer_t values: tagged, so that ids of real timers are told apart. */
#define TCS_TIMER_TAG 0x7c000000u

static uint32_t tcs_stimer_gens; /* incarnations handed out */

static struct itimerspec tcs_stimer_value(const struct tcs_stimer *t, int64_t v)
{
	struct itimerspec out = { 0 };
	int64_t next = tcs_stimer_next(t, v);
	if (next != TCS_NEVER)
		out.it_value = tcs_ns_to_ts(next - v);
	out.it_interval = tcs_ns_to_ts(t->interval);
	return out;
}

/* What is left of slot now, as getitimer and timer_gettime read it. The
 * time is read before the lock (a read may spin, which must not hold
 * signals off), so a handler that set the timer between the two (a legacy
 * loop's re-arm) made its setting from a later time: read again then, or
 * more is left than was set. */
static struct itimerspec tcs_stimer_read(int slot)
{
	const struct tcs_stimer *t = &tcs_stimers[slot];
	for (;;) {
		uint32_t count = __atomic_load_n(&t->set_count, __ATOMIC_RELAXED);
		int64_t now = tcs_timer_read_vnow();
		uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_STIMERS]);
		struct itimerspec v = tcs_stimer_value(t, now);
		int same = t->set_count == count;
		tcs_unlock(&tcs_locks[TCS_LOCK_STIMERS], signals);
		if (same)
			return v;
	}
}

/* Tells the coordinator what slot is set to now; 0 or -errno. A signal
 * handler may set it again while this is under way, its own telling going
 * first: so what goes is the table's latest, again until nothing newer
 * came meanwhile. */
static long tcs_stimer_sync(int slot)
{
	if (!tcs_wait_enter())
		return -EBUSY;
	long r = 0;
	uint32_t told;
	do {
		uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_STIMERS]);
		struct tcs_stimer t = tcs_stimers[slot];
		tcs_unlock(&tcs_locks[TCS_LOCK_STIMERS], signals);
		told = t.set_count;
		if (!t.signo)
			break; /* SIGEV_NONE: nothing to send */
		struct tcs_msg m = tcs_msg_make(TCS_MSG_TIMER, 0), w;
		m.flags = (uint16_t)slot;
		m.kind = (uint16_t)t.signo;
		m.deadline = t.first;
		m.arg = t.interval;
		m.v = t.tid;
		m.cpu = tcs_charge_point(TCS_MSG_TIMER);
		tcs_roundtrip(&m, NULL, 0, NULL, &w, NULL);
		r = w.arg < 0 ? w.arg : 0;
	} while (__atomic_load_n(&tcs_stimers[slot].set_count, __ATOMIC_RELAXED) != told);
	tcs_wait_leave();
	return r;
}

/* Arms slot with a value and interval in ns (value 0: disarm); *old gets
 * what was left. abs: value is a time of t->clock. */
static long tcs_stimer_set(int slot, int64_t value, int64_t interval, int abs, struct itimerspec *old)
{
	struct tcs_stimer *t = &tcs_stimers[slot];
	int64_t v = tcs_vnow();
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_STIMERS]);
	if (old)
		*old = tcs_stimer_value(t, v);
	if (value <= 0)
		t->first = TCS_NEVER;
	else
		t->first = abs ? value - tcs_sleep_clock_origin(t->clock) : tcs_ns_add(v, value);
	t->interval = t->first == TCS_NEVER ? 0 : interval;
	__atomic_add_fetch(&t->set_count, 1, __ATOMIC_RELAXED);
	int helper = t->notify != NULL;
	tcs_unlock(&tcs_locks[TCS_LOCK_STIMERS], signals);
	if (helper) {
		tcs_timer_threads_poke();
		return 0;
	}
	return tcs_stimer_sync(slot);
}

/* ---- ITIMER_REAL and alarm --------------------------------------------------- */

static struct timeval tcs_ts_to_tv(struct timespec ts)
{
	struct timeval tv = { ts.tv_sec, ts.tv_nsec / 1000 };
	return tv;
}

TCS_EXPORT int setitimer(__itimer_which_t which, const struct itimerval *val, struct itimerval *old)
{
	if (which != ITIMER_REAL || !tcs_active())
		return tcs_errno_result(tcs_sys3(SYS_setitimer, which, val, old));
	if (!val || val->it_value.tv_usec < 0 || val->it_value.tv_usec >= 1000000 || val->it_interval.tv_usec < 0 ||
	    val->it_interval.tv_usec >= 1000000 || val->it_value.tv_sec < 0 || val->it_interval.tv_sec < 0)
		return tcs_errno_result(-EINVAL);
	struct tcs_stimer *t = &tcs_stimers[0];
	t->used = 1;
	t->signo = SIGALRM;
	t->tid = 0;
	t->clock = CLOCK_REALTIME;
	struct itimerspec was;
	int64_t value = (int64_t)val->it_value.tv_sec * TCS_NS_PER_S + val->it_value.tv_usec * 1000;
	int64_t interval = (int64_t)val->it_interval.tv_sec * TCS_NS_PER_S + val->it_interval.tv_usec * 1000;
	long r = tcs_stimer_set(0, value, interval, 0, &was);
	if (old) {
		old->it_value = tcs_ts_to_tv(was.it_value);
		old->it_interval = tcs_ts_to_tv(was.it_interval);
	}
	return tcs_errno_result(r);
}

TCS_EXPORT int getitimer(__itimer_which_t which, struct itimerval *cur)
{
	if (which != ITIMER_REAL || !tcs_active())
		return tcs_errno_result(tcs_sys2(SYS_getitimer, which, cur));
	struct itimerspec v = tcs_stimer_read(0);
	cur->it_value = tcs_ts_to_tv(v.it_value);
	cur->it_interval = tcs_ts_to_tv(v.it_interval);
	return 0;
}

TCS_EXPORT unsigned alarm(unsigned seconds)
{
	struct itimerval val = { { 0, 0 }, { (time_t)seconds, 0 } }, old;
	if (setitimer(ITIMER_REAL, &val, &old) != 0)
		return 0;
	/* Rounded up, as the kernel does: a pending alarm never reads 0. */
	return (unsigned)(old.it_value.tv_sec + (old.it_value.tv_usec > 0 ? 1 : 0));
}

/* ---- POSIX timers ------------------------------------------------------------- */

static int tcs_timer_slot(timer_t id)
{
	uintptr_t v = (uintptr_t)id;
	if ((v & ~(uintptr_t)0xffff) != TCS_TIMER_TAG || (v & 0xffff) == 0 || (v & 0xffff) >= TCS_MAX_TIMERS)
		return -1;
	int slot = (int)(v & 0xffff);
	return tcs_stimers[slot].used ? slot : -1;
}

TCS_EXPORT int timer_create(clockid_t clock, struct sigevent *sev, timer_t *id)
{
	int notify = sev ? sev->sigev_notify : SIGEV_SIGNAL;
	if (!tcs_active()) {
		int (*real)(clockid_t, struct sigevent *, timer_t *) = tcs_real()->timer_create;
		return real ? real(clock, sev, id) : tcs_errno_result(-ENOSYS);
	}
	if (tcs_sleep_clock_origin(clock) < 0 || (notify != SIGEV_SIGNAL && notify != SIGEV_NONE &&
						    notify != SIGEV_THREAD_ID && notify != SIGEV_THREAD))
		return tcs_errno_result(-EINVAL);
	if (notify == SIGEV_THREAD && !sev->sigev_notify_function)
		return tcs_errno_result(-EINVAL);
	int signo = notify == SIGEV_NONE || notify == SIGEV_THREAD ? 0 : sev ? sev->sigev_signo : SIGALRM;
	if (signo == 0 ? notify == SIGEV_SIGNAL || notify == SIGEV_THREAD_ID : signo < 1 || signo > 64)
		return tcs_errno_result(-EINVAL);
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_STIMERS]);
	int slot = -1;
	for (int i = 1; i < TCS_MAX_TIMERS && slot < 0; i++)
		if (!tcs_stimers[i].used)
			slot = i;
	if (slot < 0) {
		tcs_unlock(&tcs_locks[TCS_LOCK_STIMERS], signals);
		return tcs_errno_result(-EAGAIN);
	}
	struct tcs_stimer *t = &tcs_stimers[slot];
	*t = (struct tcs_stimer){ 0 };
	t->used = 1;
	t->signo = signo;
	t->tid = notify == SIGEV_THREAD_ID ? sev->_sigev_un._tid : 0;
	t->clock = clock;
	t->first = TCS_NEVER;
	t->gen = ++tcs_stimer_gens;
	if (notify == SIGEV_THREAD) {
		t->notify = sev->sigev_notify_function;
		t->value = sev->sigev_value;
	}
	uint32_t gen = t->gen;
	tcs_unlock(&tcs_locks[TCS_LOCK_STIMERS], signals);
	if (notify == SIGEV_THREAD) {
		long r = tcs_timer_thread_start(slot, gen, sev);
		if (r < 0) {
			tcs_stimers[slot].used = 0;
			return tcs_errno_result(r == -EPERM ? -EAGAIN : r);
		}
	}
	*id = (timer_t)(uintptr_t)(TCS_TIMER_TAG | (unsigned)slot);
	return 0;
}

TCS_EXPORT int timer_settime(timer_t id, int flags, const struct itimerspec *val, struct itimerspec *old)
{
	int slot = tcs_timer_slot(id);
	if (slot < 0) {
		int (*real)(timer_t, int, const struct itimerspec *, struct itimerspec *) = tcs_real()->timer_settime;
		return real ? real(id, flags, val, old) : tcs_errno_result(-EINVAL);
	}
	if (!val || !tcs_ts_valid(&val->it_value) || !tcs_ts_valid(&val->it_interval))
		return tcs_errno_result(-EINVAL);
	return tcs_errno_result(tcs_stimer_set(slot, tcs_ts_to_ns(&val->it_value), tcs_ts_to_ns(&val->it_interval),
					       (flags & TIMER_ABSTIME) != 0, old));
}

TCS_EXPORT int timer_gettime(timer_t id, struct itimerspec *cur)
{
	int slot = tcs_timer_slot(id);
	if (slot < 0) {
		int (*real)(timer_t, struct itimerspec *) = tcs_real()->timer_gettime;
		return real ? real(id, cur) : tcs_errno_result(-EINVAL);
	}
	*cur = tcs_stimer_read(slot);
	return 0;
}

TCS_EXPORT int timer_getoverrun(timer_t id)
{
	int slot = tcs_timer_slot(id);
	if (slot < 0) {
		int (*real)(timer_t) = tcs_real()->timer_getoverrun;
		return real ? real(id) : tcs_errno_result(-EINVAL);
	}
	/* Signals: expirations are signalled one by one. SIGEV_THREAD: those
	 * that passed while the previous call ran. */
	return tcs_stimers[slot].overrun;
}

TCS_EXPORT int timer_delete(timer_t id)
{
	int slot = tcs_timer_slot(id);
	if (slot < 0) {
		int (*real)(timer_t) = tcs_real()->timer_delete;
		return real ? real(id) : tcs_errno_result(-EINVAL);
	}
	long r = tcs_stimer_set(slot, 0, 0, 0, NULL);
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_STIMERS]);
	int helper = tcs_stimers[slot].notify != NULL;
	tcs_stimers[slot].used = 0;
	tcs_unlock(&tcs_locks[TCS_LOCK_STIMERS], signals);
	if (helper)
		tcs_timer_threads_poke(); /* its helper ends */
	return tcs_errno_result(r);
}
