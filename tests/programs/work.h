/* What test controllers share: a fixed amount of computation (n rounds of
 * integer arithmetic the compiler cannot remove, whose CPU cost `calibrate`
 * measures natively, so a test knows what the work should cost) and a clock
 * read in nanoseconds. */
#ifndef TCS_TEST_WORK_H
#define TCS_TEST_WORK_H

#include <stdint.h>
#include <time.h>

static inline long long clock_ns(clockid_t clock)
{
	struct timespec ts;
	clock_gettime(clock, &ts);
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

/* A CPU-time clock as the kernel keeps it, read with a system call
 * instruction of our own: libc's clock_gettime and syscall() are tcs's
 * hooks, which answer with virtual CPU. Work measured on it is real work,
 * so a test that compares virtual time with it checks tcs's charging
 * against the kernel's, not against itself. */
static inline long long kernel_clock_ns(clockid_t clock)
{
	struct timespec ts = { 0, 0 };
#if defined(__x86_64__)
	long ret;
	__asm__ volatile("syscall"
			 : "=a"(ret)
			 : "0"(228L /* SYS_clock_gettime */), "D"((long)clock), "S"(&ts)
			 : "rcx", "r11", "memory");
	(void)ret;
#else
#error "kernel_clock_ns: a raw system call for this architecture"
#endif
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static inline long long kernel_cpu_ns(void)
{
	return kernel_clock_ns(CLOCK_PROCESS_CPUTIME_ID);
}

/* getrusage(who) by the kernel's account, with a system call instruction
 * of our own, as above. */
struct raw_rusage {
	long utime_s, utime_us, stime_s, stime_us;
	long maxrss, ixrss, idrss, isrss, minflt, majflt, nswap, inblock, oublock, msgsnd, msgrcv, nsignals;
	long nvcsw, nivcsw;
};

static inline struct raw_rusage kernel_rusage(long who)
{
	struct raw_rusage ru = { 0 };
#if defined(__x86_64__)
	long ret;
	__asm__ volatile("syscall"
			 : "=a"(ret)
			 : "0"(98L /* SYS_getrusage */), "D"(who), "S"(&ru)
			 : "rcx", "r11", "memory");
	(void)ret;
#else
#error "kernel_rusage: a raw system call for this architecture"
#endif
	return ru;
}

/* The CPU of this process's children that it has waited for (user and
 * system): RUSAGE_CHILDREN. */
static inline long long kernel_children_cpu_ns(void)
{
	struct raw_rusage ru = kernel_rusage(-1L /* RUSAGE_CHILDREN */);
	return (ru.utime_s + ru.stime_s) * 1000000000LL + (ru.utime_us + ru.stime_us) * 1000LL;
}

/* How many times this process gave up its core (RUSAGE_SELF's voluntary
 * context switches): each of its waits, and each stop tcs made (a stop's
 * cost is left out of what tcs charges; this bounds how many there were). */
static inline long kernel_voluntary_switches(void)
{
	return kernel_rusage(0L /* RUSAGE_SELF */).nvcsw;
}

/* How many times the calling thread gave up its core (RUSAGE_THREAD's
 * voluntary switches): around computation that makes no wait, the stops
 * tcs made of it. */
static inline long kernel_thread_voluntary_switches(void)
{
	return kernel_rusage(1L /* RUSAGE_THREAD */).nvcsw;
}

static inline uint64_t work(uint64_t n)
{
	static volatile uint64_t sink;
	uint64_t x = sink + 88172645463325252ull;
	for (uint64_t i = 0; i < n; i++) {
		x ^= x << 13;
		x ^= x >> 7;
		x ^= x << 17;
	}
	sink = x;
	return x;
}

/* Computes until `clock` (a CPU-time clock) has advanced ns by the
 * kernel's account; returns how far it did. */
static inline long long compute_ns(clockid_t clock, long long ns)
{
	long long c0 = kernel_clock_ns(clock), used = 0;
	while ((used = kernel_clock_ns(clock) - c0) < ns)
		work(100);
	return used;
}

#endif
