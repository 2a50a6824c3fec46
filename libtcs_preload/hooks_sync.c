/* Waits of one thread for another, in virtual time: condition variables
 * (pthread_cond_wait, _timedwait in both glibc versions, _clockwait),
 * semaphores (sem_wait, sem_timedwait, sem_clockwait) and timed mutex locks
 * (pthread_mutex_timedlock, _clocklock). A waiting thread parks
 * (parking.c); the signalling side (pthread_cond_signal/broadcast, sem_post,
 * pthread_mutex_unlock) does the real thing, then wakes the parked. A
 * timeout is a virtual deadline on the clock the object or call names.
 * These are what C++ std::condition_variable and Python's threading (locks,
 * Event, queue, and its GIL) are built on. */
#include <pthread.h>
#include <semaphore.h>

#include "parking.h"
#include "raw_syscall.h"
#include "real.h"
#include "vclock.h"
#include "wait.h"

/* Every hook here takes the real functions with tcs_real() first, before
 * anything else: a library's constructor may lock a mutex before the
 * preload's own constructor has run. The helpers below them then read the
 * table directly. */
typedef int (*tcs_cond_fn)(pthread_cond_t *);

/* An absolute time on clock into a virtual deadline; -EINVAL if invalid. */
static int64_t tcs_abs_deadline(clockid_t clock, const struct timespec *abstime)
{
	if (!abstime)
		return TCS_NEVER;
	if (!tcs_ts_valid(abstime))
		return -EINVAL;
	int64_t origin = tcs_sleep_clock_origin(clock);
	if (origin < 0)
		return -EINVAL;
	int64_t t = tcs_ts_to_ns(abstime);
	return t > origin ? t - origin : 0;
}

/* ---- mutexes ------------------------------------------------------------ */

TCS_EXPORT int pthread_mutex_unlock(pthread_mutex_t *m)
{
	const struct tcs_real_fns *real = tcs_real();
	int r = real->pthread_mutex_unlock(m);
	if (r == 0)
		tcs_unpark(m);
	return r;
}

/* A timed lock: try, park until an unlock (or the deadline), try again. */
static int tcs_mutex_timedlock(pthread_mutex_t *m, clockid_t clock, const struct timespec *abstime)
{
	int r = tcs_real_fns.pthread_mutex_trylock(m);
	if (r != EBUSY)
		return r;
	int64_t deadline = tcs_abs_deadline(clock, abstime);
	if (deadline < 0)
		return EINVAL;
	/* Already its owner: an error-checking mutex says so, any other
	 * waits out its time. */
	if (m->__data.__owner == (int)tcs_sys0(SYS_gettid) && (m->__data.__kind & 3) == PTHREAD_MUTEX_ERRORCHECK)
		return EDEADLK;
	for (;;) {
		struct tcs_wait_time t = { deadline, 0, 0, 0, 0, 0 };
		int slot = tcs_park_begin(m);
		r = tcs_real_fns.pthread_mutex_trylock(m);
		if (r != EBUSY) {
			tcs_park_end(slot);
			return r;
		}
		int w = tcs_park_wait(slot, &t, 0);
		tcs_park_end(slot);
		r = tcs_real_fns.pthread_mutex_trylock(m);
		if (r != EBUSY)
			return r;
		if (w == TCS_WAIT_DEADLINE)
			return ETIMEDOUT;
		/* Woken (an unlock someone else got first), or a signal: a mutex
		 * wait is not interrupted. Wait on. */
	}
}

TCS_EXPORT int pthread_mutex_timedlock(pthread_mutex_t *m, const struct timespec *abstime)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->pthread_mutex_timedlock(m, abstime);
	int r = tcs_mutex_timedlock(m, CLOCK_REALTIME, abstime);
	tcs_wait_leave();
	return r;
}

TCS_EXPORT int pthread_mutex_clocklock(pthread_mutex_t *m, clockid_t clock, const struct timespec *abstime)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->pthread_mutex_clocklock(m, clock, abstime);
	int r = clock == CLOCK_REALTIME || clock == CLOCK_MONOTONIC ? tcs_mutex_timedlock(m, clock, abstime) : EINVAL;
	tcs_wait_leave();
	return r;
}

/* ---- condition variables ------------------------------------------------ */

/* The clock a condition variable's timed waits use (pthread_condattr_setclock):
 * glibc keeps it in bit 1 of __wrefs (0: CLOCK_REALTIME, 1: CLOCK_MONOTONIC). */
static clockid_t tcs_cond_clock(const pthread_cond_t *c)
{
	return (__atomic_load_n(&c->__data.__wrefs, __ATOMIC_RELAXED) & 2) ? CLOCK_MONOTONIC : CLOCK_REALTIME;
}

/* Parks on cond with mutex released (registered first, so a signal after
 * the release is never lost); returns with mutex locked again, as POSIX
 * says: 0 (signalled, or a spurious wake-up), ETIMEDOUT, or the relock's
 * error (EOWNERDEAD). */
static int tcs_cond_wait(const void *cond, pthread_mutex_t *mutex, clockid_t clock, const struct timespec *abstime)
{
	int64_t deadline = tcs_abs_deadline(clock, abstime);
	if (deadline < 0)
		return EINVAL;
	struct tcs_wait_time t = { deadline, 0, 0, 0, 0, 0 };
	int slot = tcs_park_begin(cond);
	int r = pthread_mutex_unlock(mutex);
	if (r) {
		tcs_park_end(slot);
		return r;
	}
	int w = tcs_park_wait(slot, &t, 0);
	tcs_park_end(slot);
	r = tcs_real_fns.pthread_mutex_lock(mutex);
	if (r)
		return r;
	return abstime && w == TCS_WAIT_DEADLINE ? ETIMEDOUT : 0;
}

static int tcs_cond_wake(pthread_cond_t *c, tcs_cond_fn fn)
{
	int r = fn(c);
	tcs_unpark(c);
	return r;
}

int tcs_cond_wait_new(pthread_cond_t *c, pthread_mutex_t *m) TCS_EXPORT;
int tcs_cond_wait_new(pthread_cond_t *c, pthread_mutex_t *m)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->pthread_cond_wait(c, m);
	int r = tcs_cond_wait(c, m, CLOCK_REALTIME, NULL);
	tcs_wait_leave();
	return r;
}

int tcs_cond_timedwait_new(pthread_cond_t *c, pthread_mutex_t *m, const struct timespec *abstime) TCS_EXPORT;
int tcs_cond_timedwait_new(pthread_cond_t *c, pthread_mutex_t *m, const struct timespec *abstime)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->pthread_cond_timedwait(c, m, abstime);
	int r = tcs_cond_wait(c, m, tcs_cond_clock(c), abstime);
	tcs_wait_leave();
	return r;
}

int tcs_cond_signal_new(pthread_cond_t *c) TCS_EXPORT;
int tcs_cond_signal_new(pthread_cond_t *c)
{
	const struct tcs_real_fns *real = tcs_real();
	return tcs_cond_wake(c, real->pthread_cond_signal);
}

int tcs_cond_broadcast_new(pthread_cond_t *c) TCS_EXPORT;
int tcs_cond_broadcast_new(pthread_cond_t *c)
{
	const struct tcs_real_fns *real = tcs_real();
	return tcs_cond_wake(c, real->pthread_cond_broadcast);
}

TCS_EXPORT int pthread_cond_clockwait(pthread_cond_t *c, pthread_mutex_t *m, clockid_t clock,
				      const struct timespec *abstime)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->pthread_cond_clockwait(c, m, clock, abstime);
	int r = clock == CLOCK_REALTIME || clock == CLOCK_MONOTONIC ? tcs_cond_wait(c, m, clock, abstime) : EINVAL;
	tcs_wait_leave();
	return r;
}

#if defined(__x86_64__)
/* glibc keeps the condition variables of before 2.3.2 for old binaries: a
 * different object (only its address matters here), timed on CLOCK_REALTIME. */
int tcs_cond_wait_old(pthread_cond_t *c, pthread_mutex_t *m) TCS_EXPORT;
int tcs_cond_wait_old(pthread_cond_t *c, pthread_mutex_t *m)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->pthread_cond_wait_old(c, m);
	int r = tcs_cond_wait(c, m, CLOCK_REALTIME, NULL);
	tcs_wait_leave();
	return r;
}

int tcs_cond_timedwait_old(pthread_cond_t *c, pthread_mutex_t *m, const struct timespec *abstime) TCS_EXPORT;
int tcs_cond_timedwait_old(pthread_cond_t *c, pthread_mutex_t *m, const struct timespec *abstime)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->pthread_cond_timedwait_old(c, m, abstime);
	int r = tcs_cond_wait(c, m, CLOCK_REALTIME, abstime);
	tcs_wait_leave();
	return r;
}

int tcs_cond_signal_old(pthread_cond_t *c) TCS_EXPORT;
int tcs_cond_signal_old(pthread_cond_t *c)
{
	const struct tcs_real_fns *real = tcs_real();
	return tcs_cond_wake(c, real->pthread_cond_signal_old);
}

int tcs_cond_broadcast_old(pthread_cond_t *c) TCS_EXPORT;
int tcs_cond_broadcast_old(pthread_cond_t *c)
{
	const struct tcs_real_fns *real = tcs_real();
	return tcs_cond_wake(c, real->pthread_cond_broadcast_old);
}

__asm__(".symver tcs_cond_wait_new, pthread_cond_wait@@GLIBC_2.3.2");
__asm__(".symver tcs_cond_timedwait_new, pthread_cond_timedwait@@GLIBC_2.3.2");
__asm__(".symver tcs_cond_signal_new, pthread_cond_signal@@GLIBC_2.3.2");
__asm__(".symver tcs_cond_broadcast_new, pthread_cond_broadcast@@GLIBC_2.3.2");
__asm__(".symver tcs_cond_wait_old, pthread_cond_wait@GLIBC_2.2.5");
__asm__(".symver tcs_cond_timedwait_old, pthread_cond_timedwait@GLIBC_2.2.5");
__asm__(".symver tcs_cond_signal_old, pthread_cond_signal@GLIBC_2.2.5");
__asm__(".symver tcs_cond_broadcast_old, pthread_cond_broadcast@GLIBC_2.2.5");
#else
TCS_EXPORT int pthread_cond_wait(pthread_cond_t *, pthread_mutex_t *) __attribute__((alias("tcs_cond_wait_new")));
TCS_EXPORT int pthread_cond_timedwait(pthread_cond_t *, pthread_mutex_t *, const struct timespec *)
	__attribute__((alias("tcs_cond_timedwait_new")));
TCS_EXPORT int pthread_cond_signal(pthread_cond_t *) __attribute__((alias("tcs_cond_signal_new")));
TCS_EXPORT int pthread_cond_broadcast(pthread_cond_t *) __attribute__((alias("tcs_cond_broadcast_new")));
#endif

/* ---- semaphores --------------------------------------------------------- */

/* A semaphore shared between processes (sem_open, or sem_init with
 * pshared): a post in another process cannot wake a parked thread here, so
 * its wait re-checks at every step. glibc's sem_t holds, after its 64-bit
 * value, the futex flag its waits use: 0 for a private semaphore, and
 * FUTEX_PRIVATE_FLAG (128), confusingly, for a shared one (glibc's
 * LLL_SHARED). */
static int tcs_sem_shared(const sem_t *s)
{
	const int *futex_flag = (const int *)((const char *)s + sizeof(uint64_t));
	return __atomic_load_n(futex_flag, __ATOMIC_RELAXED) != 0;
}

/* 0 or an errno value. */
static int tcs_sem_wait(sem_t *s, clockid_t clock, const struct timespec *abstime)
{
	int saved = errno;
	int r = 0;
	for (;;) {
		if (tcs_real_fns.sem_trywait(s) == 0)
			break;
		int64_t deadline = tcs_abs_deadline(clock, abstime);
		if (deadline < 0) {
			r = EINVAL;
			break;
		}
		struct tcs_wait_time t = { deadline, 0, 0, 0, 0, 0 };
		int slot = tcs_park_begin(s);
		if (tcs_real_fns.sem_trywait(s) == 0) {
			tcs_park_end(slot);
			break;
		}
		int w = tcs_park_wait(slot, &t, tcs_sem_shared(s) ? TCS_BLOCK_RECHECK : 0);
		tcs_park_end(slot);
		if (w == -EINTR) {
			r = EINTR;
			break;
		}
		if (w == TCS_WAIT_DEADLINE && abstime) {
			r = tcs_real_fns.sem_trywait(s) == 0 ? 0 : ETIMEDOUT;
			break;
		}
	}
	errno = saved;
	return r;
}

TCS_EXPORT int sem_post(sem_t *s)
{
	const struct tcs_real_fns *real = tcs_real();
	int r = real->sem_post(s);
	if (r == 0)
		tcs_unpark(s);
	return r;
}

TCS_EXPORT int sem_wait(sem_t *s)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->sem_wait(s);
	int r = tcs_sem_wait(s, CLOCK_REALTIME, NULL);
	tcs_wait_leave();
	return tcs_errno_result(-r);
}

TCS_EXPORT int sem_timedwait(sem_t *s, const struct timespec *abstime)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->sem_timedwait(s, abstime);
	int r = tcs_sem_wait(s, CLOCK_REALTIME, abstime);
	tcs_wait_leave();
	return tcs_errno_result(-r);
}

TCS_EXPORT int sem_clockwait(sem_t *s, clockid_t clock, const struct timespec *abstime)
{
	const struct tcs_real_fns *real = tcs_real();
	if (!tcs_wait_enter())
		return real->sem_clockwait(s, clock, abstime);
	int r = clock == CLOCK_REALTIME || clock == CLOCK_MONOTONIC ? tcs_sem_wait(s, clock, abstime) : EINVAL;
	tcs_wait_leave();
	return tcs_errno_result(-r);
}
