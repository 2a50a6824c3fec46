/* What the benchmark programs share: wall time for those that run under
 * tcs-run (read with a raw system call, which the preload does not see, so
 * that it is real time even when every clock the program could read is
 * virtual), and pinning to the core tcs-run would use (the last allowed). */
#ifndef TCS_BENCH_TIME_H
#define TCS_BENCH_TIME_H

#include <sched.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

static inline double bench_wall_ns(void)
{
	struct timespec ts;
	syscall(SYS_clock_gettime, CLOCK_MONOTONIC_RAW, &ts);
	return ts.tv_sec * 1e9 + ts.tv_nsec;
}

/* Pins the calling process (and what it forks) to the last allowed core. */
static inline void bench_pin_to_last_cpu(void)
{
	cpu_set_t one;
	CPU_ZERO(&one);
	sched_getaffinity(0, sizeof one, &one);
	for (int c = CPU_SETSIZE - 1; c >= 0; c--)
		if (CPU_ISSET(c, &one)) {
			CPU_ZERO(&one);
			CPU_SET(c, &one);
			break;
		}
	sched_setaffinity(0, sizeof one, &one);
}

#endif
