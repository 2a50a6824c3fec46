/* Waits of one thread for another, in virtual time: condition variables
 * (pthread_cond_wait, _timedwait in both glibc versions, _clockwait),
 * semaphores (sem_wait, sem_timedwait, sem_clockwait) and timed mutex locks
 * (pthread_mutex_timedlock, _clocklock). A waiting thread parks
 * (parking.c); the signalling side (pthread_cond_signal/broadcast, sem_post,
 * pthread_mutex_unlock) does the real thing, then wakes the parked. A
 * timeout is a virtual deadline on the clock the object or call names.
 * These are what C++ std::condition_variable and Python's threading (locks,
 * Event, queue, and its GIL) are built on. */
#include <dlfcn.h>
#include <pthread.h>
#include <semaphore.h>

#include "parking.h"
#include "raw_syscall.h"

typedef int (*tcs_cond_fn)(pthread_cond_t *);
typedef int (*tcs_cond_wait_fn)(pthread_cond_t *, pthread_mutex_t *);
typedef int (*tcs_cond_timedwait_fn)(pthread_cond_t *, pthread_mutex_t *, const struct timespec *);
typedef int (*tcs_mutex_fn)(pthread_mutex_t *);
typedef int (*tcs_sem_fn)(sem_t *);

static struct {
	int ready;
	tcs_cond_fn signal, broadcast, old_signal, old_broadcast;
	tcs_cond_wait_fn wait, old_wait;
	tcs_cond_timedwait_fn timedwait, old_timedwait;
	int (*clockwait)(pthread_cond_t *, pthread_mutex_t *, clockid_t, const struct timespec *);
	tcs_mutex_fn lock, unlock, trylock;
	int (*timedlock)(pthread_mutex_t *, const struct timespec *);
	int (*clocklock)(pthread_mutex_t *, clockid_t, const struct timespec *);
	tcs_sem_fn sem_wait, sem_trywait, sem_post;
	int (*sem_timedwait)(sem_t *, const struct timespec *);
	int (*sem_clockwait)(sem_t *, clockid_t, const struct timespec *);
} real;

/* Resolved on first use: a library's constructor may lock a mutex before
 * the preload's own constructor has run. */
static void tcs_sync_resolve(void)
{
#define TCS_REAL(field, name) real.field = (__typeof__(real.field))dlsym(RTLD_NEXT, name)
#if defined(__x86_64__)
#define TCS_REAL_V(field, name, version) real.field = (__typeof__(real.field))dlvsym(RTLD_NEXT, name, version)
	TCS_REAL_V(signal, "pthread_cond_signal", "GLIBC_2.3.2");
	TCS_REAL_V(broadcast, "pthread_cond_broadcast", "GLIBC_2.3.2");
	TCS_REAL_V(wait, "pthread_cond_wait", "GLIBC_2.3.2");
	TCS_REAL_V(timedwait, "pthread_cond_timedwait", "GLIBC_2.3.2");
	TCS_REAL_V(old_signal, "pthread_cond_signal", "GLIBC_2.2.5");
	TCS_REAL_V(old_broadcast, "pthread_cond_broadcast", "GLIBC_2.2.5");
	TCS_REAL_V(old_wait, "pthread_cond_wait", "GLIBC_2.2.5");
	TCS_REAL_V(old_timedwait, "pthread_cond_timedwait", "GLIBC_2.2.5");
#else
	TCS_REAL(signal, "pthread_cond_signal");
	TCS_REAL(broadcast, "pthread_cond_broadcast");
	TCS_REAL(wait, "pthread_cond_wait");
	TCS_REAL(timedwait, "pthread_cond_timedwait");
#endif
	TCS_REAL(clockwait, "pthread_cond_clockwait");
	TCS_REAL(lock, "pthread_mutex_lock");
	TCS_REAL(unlock, "pthread_mutex_unlock");
	TCS_REAL(trylock, "pthread_mutex_trylock");
	TCS_REAL(timedlock, "pthread_mutex_timedlock");
	TCS_REAL(clocklock, "pthread_mutex_clocklock");
	TCS_REAL(sem_wait, "sem_wait");
	TCS_REAL(sem_trywait, "sem_trywait");
	TCS_REAL(sem_post, "sem_post");
	TCS_REAL(sem_timedwait, "sem_timedwait");
	TCS_REAL(sem_clockwait, "sem_clockwait");
	__atomic_store_n(&real.ready, 1, __ATOMIC_RELEASE);
}

#define TCS_SYNC_READY()                                              \
	do {                                                          \
		if (!__atomic_load_n(&real.ready, __ATOMIC_ACQUIRE)) \
			tcs_sync_resolve();                           \
	} while (0)

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
	TCS_SYNC_READY();
	int r = real.unlock(m);
	if (r == 0)
		tcs_unpark(m);
	return r;
}

/* A timed lock: try, park until an unlock (or the deadline), try again. */
static int tcs_mutex_timedlock(pthread_mutex_t *m, clockid_t clock, const struct timespec *abstime)
{
	int r = real.trylock(m);
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
		struct tcs_wait_time t = { deadline, 0, 0, 0, 0 };
		int slot = tcs_park_begin(m);
		r = real.trylock(m);
		if (r != EBUSY) {
			tcs_park_end(slot);
			return r;
		}
		int w = tcs_park_wait(slot, &t, 0);
		tcs_park_end(slot);
		r = real.trylock(m);
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
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.timedlock(m, abstime);
	int r = tcs_mutex_timedlock(m, CLOCK_REALTIME, abstime);
	tcs_wait_leave();
	return r;
}

TCS_EXPORT int pthread_mutex_clocklock(pthread_mutex_t *m, clockid_t clock, const struct timespec *abstime)
{
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.clocklock(m, clock, abstime);
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
	struct tcs_wait_time t = { deadline, 0, 0, 0, 0 };
	int slot = tcs_park_begin(cond);
	int r = pthread_mutex_unlock(mutex);
	if (r) {
		tcs_park_end(slot);
		return r;
	}
	int w = tcs_park_wait(slot, &t, 0);
	tcs_park_end(slot);
	r = real.lock(mutex);
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
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.wait(c, m);
	int r = tcs_cond_wait(c, m, CLOCK_REALTIME, NULL);
	tcs_wait_leave();
	return r;
}

int tcs_cond_timedwait_new(pthread_cond_t *c, pthread_mutex_t *m, const struct timespec *abstime) TCS_EXPORT;
int tcs_cond_timedwait_new(pthread_cond_t *c, pthread_mutex_t *m, const struct timespec *abstime)
{
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.timedwait(c, m, abstime);
	int r = tcs_cond_wait(c, m, tcs_cond_clock(c), abstime);
	tcs_wait_leave();
	return r;
}

int tcs_cond_signal_new(pthread_cond_t *c) TCS_EXPORT;
int tcs_cond_signal_new(pthread_cond_t *c)
{
	TCS_SYNC_READY();
	return tcs_cond_wake(c, real.signal);
}

int tcs_cond_broadcast_new(pthread_cond_t *c) TCS_EXPORT;
int tcs_cond_broadcast_new(pthread_cond_t *c)
{
	TCS_SYNC_READY();
	return tcs_cond_wake(c, real.broadcast);
}

TCS_EXPORT int pthread_cond_clockwait(pthread_cond_t *c, pthread_mutex_t *m, clockid_t clock,
				      const struct timespec *abstime)
{
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.clockwait(c, m, clock, abstime);
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
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.old_wait(c, m);
	int r = tcs_cond_wait(c, m, CLOCK_REALTIME, NULL);
	tcs_wait_leave();
	return r;
}

int tcs_cond_timedwait_old(pthread_cond_t *c, pthread_mutex_t *m, const struct timespec *abstime) TCS_EXPORT;
int tcs_cond_timedwait_old(pthread_cond_t *c, pthread_mutex_t *m, const struct timespec *abstime)
{
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.old_timedwait(c, m, abstime);
	int r = tcs_cond_wait(c, m, CLOCK_REALTIME, abstime);
	tcs_wait_leave();
	return r;
}

int tcs_cond_signal_old(pthread_cond_t *c) TCS_EXPORT;
int tcs_cond_signal_old(pthread_cond_t *c)
{
	TCS_SYNC_READY();
	return tcs_cond_wake(c, real.old_signal);
}

int tcs_cond_broadcast_old(pthread_cond_t *c) TCS_EXPORT;
int tcs_cond_broadcast_old(pthread_cond_t *c)
{
	TCS_SYNC_READY();
	return tcs_cond_wake(c, real.old_broadcast);
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
		if (real.sem_trywait(s) == 0)
			break;
		int64_t deadline = tcs_abs_deadline(clock, abstime);
		if (deadline < 0) {
			r = EINVAL;
			break;
		}
		struct tcs_wait_time t = { deadline, 0, 0, 0, 0 };
		int slot = tcs_park_begin(s);
		if (real.sem_trywait(s) == 0) {
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
			r = real.sem_trywait(s) == 0 ? 0 : ETIMEDOUT;
			break;
		}
	}
	errno = saved;
	return r;
}

TCS_EXPORT int sem_post(sem_t *s)
{
	TCS_SYNC_READY();
	int r = real.sem_post(s);
	if (r == 0)
		tcs_unpark(s);
	return r;
}

TCS_EXPORT int sem_wait(sem_t *s)
{
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.sem_wait(s);
	int r = tcs_sem_wait(s, CLOCK_REALTIME, NULL);
	tcs_wait_leave();
	return tcs_errno_result(-r);
}

TCS_EXPORT int sem_timedwait(sem_t *s, const struct timespec *abstime)
{
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.sem_timedwait(s, abstime);
	int r = tcs_sem_wait(s, CLOCK_REALTIME, abstime);
	tcs_wait_leave();
	return tcs_errno_result(-r);
}

TCS_EXPORT int sem_clockwait(sem_t *s, clockid_t clock, const struct timespec *abstime)
{
	TCS_SYNC_READY();
	if (!tcs_wait_enter())
		return real.sem_clockwait(s, clock, abstime);
	int r = clock == CLOCK_REALTIME || clock == CLOCK_MONOTONIC ? tcs_sem_wait(s, clock, abstime) : EINVAL;
	tcs_wait_leave();
	return tcs_errno_result(-r);
}
