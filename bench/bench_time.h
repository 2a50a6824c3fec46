/* Wall time for benchmarks that run under tcs-run: read with a raw system
 * call, which the preload does not see, so that it is real time even when
 * every clock the program could read is virtual. */
#ifndef TCS_BENCH_TIME_H
#define TCS_BENCH_TIME_H

#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

static inline double bench_wall_ns(void)
{
	struct timespec ts;
	syscall(SYS_clock_gettime, CLOCK_MONOTONIC_RAW, &ts);
	return ts.tv_sec * 1e9 + ts.tv_nsec;
}

#endif
