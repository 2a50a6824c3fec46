/* futex_wait: futex waits with a timeout made through syscall(SYS_futex),
 * as libstdc++'s atomic waits and hand-written locks make them, each timed
 * on CLOCK_MONOTONIC (ns) and printed as key=value lines with what the call
 * returned (ret, errno's name):
 *   relative  FUTEX_WAIT_PRIVATE, 2 ms relative, nobody wakes it
 *   absolute  FUTEX_WAIT_BITSET, absolute CLOCK_MONOTONIC deadline 3 ms on
 *   realtime  FUTEX_WAIT_BITSET | FUTEX_CLOCK_REALTIME, 4 ms on
 *   changed   FUTEX_WAIT whose word no longer holds the value (EAGAIN)
 *   woken     FUTEX_WAIT for 10 ms, woken by another thread's FUTEX_WAKE
 *             after that thread's 1 ms sleep */
#include <errno.h>
#include <linux/futex.h>
#include <pthread.h>
#include <stdio.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#define MS 1000000LL

static int word;

static long long now(clockid_t c)
{
	struct timespec t;
	clock_gettime(c, &t);
	return t.tv_sec * 1000000000LL + t.tv_nsec;
}

static struct timespec ts(long long ns)
{
	struct timespec t = { (time_t)(ns / 1000000000LL), (long)(ns % 1000000000LL) };
	return t;
}

static const char *errno_name(long r, int e)
{
	if (r >= 0)
		return "none";
	return e == ETIMEDOUT ? "ETIMEDOUT" : e == EAGAIN ? "EAGAIN" : e == EINTR ? "EINTR" : e == EINVAL ? "EINVAL" : "other";
}

/* One wait: its span on CLOCK_MONOTONIC and what it returned. */
static void timed(const char *name, int op, int val, const struct timespec *t)
{
	long long t0 = now(CLOCK_MONOTONIC);
	errno = 0;
	long r = syscall(SYS_futex, &word, op, val, t, NULL, FUTEX_BITSET_MATCH_ANY);
	int e = errno;
	long long t1 = now(CLOCK_MONOTONIC);
	printf("%s_ns=%lld\n%s_ret=%ld\n%s_errno=%s\n", name, t1 - t0, name, r, name, errno_name(r, e));
}

static void *waker(void *arg)
{
	(void)arg;
	struct timespec d = ts(MS);
	nanosleep(&d, NULL);
	__atomic_store_n(&word, 1, __ATOMIC_SEQ_CST);
	syscall(SYS_futex, &word, FUTEX_WAKE_PRIVATE, 1, NULL, NULL, 0);
	return NULL;
}

int main(void)
{
	struct timespec rel = ts(2 * MS);
	timed("relative", FUTEX_WAIT_PRIVATE, 0, &rel);
	struct timespec abs_mono = ts(now(CLOCK_MONOTONIC) + 3 * MS);
	timed("absolute", FUTEX_WAIT_BITSET_PRIVATE, 0, &abs_mono);
	struct timespec abs_real = ts(now(CLOCK_REALTIME) + 4 * MS);
	timed("realtime", FUTEX_WAIT_BITSET_PRIVATE | FUTEX_CLOCK_REALTIME, 0, &abs_real);
	timed("changed", FUTEX_WAIT_PRIVATE, 7, &rel);
	pthread_t th;
	struct timespec ten = ts(10 * MS);
	pthread_create(&th, NULL, waker, NULL);
	long long t0 = now(CLOCK_MONOTONIC);
	errno = 0;
	long r = 0;
	/* (A wake that comes first leaves the word changed: EAGAIN, no wait.) */
	while (__atomic_load_n(&word, __ATOMIC_SEQ_CST) == 0 && r == 0)
		r = syscall(SYS_futex, &word, FUTEX_WAIT_PRIVATE, 0, &ten, NULL, 0);
	int e = errno;
	long long t1 = now(CLOCK_MONOTONIC);
	pthread_join(th, NULL);
	printf("woken_ns=%lld\nwoken_ret=%ld\nwoken_errno=%s\n", t1 - t0, r, errno_name(r, e));
	return 0;
}
