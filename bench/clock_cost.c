/* clock_cost [N] [cpu]: nanoseconds per clock_gettime(CLOCK_MONOTONIC) call,
 * as a controller calls it (natively: the vDSO; under tcs-run: the hook);
 * with `cpu`, per clock_gettime(CLOCK_PROCESS_CPUTIME_ID), the system call
 * whose cost decides tcs's slow paths (bench/run.py's machine facts). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_time.h"

int main(int argc, char **argv)
{
	long n = argc > 1 ? atol(argv[1]) : 20000000;
	clockid_t clock = argc > 2 && strcmp(argv[2], "cpu") == 0 ? CLOCK_PROCESS_CPUTIME_ID : CLOCK_MONOTONIC;
	struct timespec ts;
	long long sink = 0;
	for (long i = 0; i < n / 10; i++) { /* warm up */
		clock_gettime(clock, &ts);
		sink += ts.tv_nsec;
	}
	double t0 = bench_wall_ns();
	for (long i = 0; i < n; i++) {
		clock_gettime(clock, &ts);
		sink += ts.tv_nsec;
	}
	double t1 = bench_wall_ns();
	printf("clock_gettime_ns=%.2f (sink %lld)\n", (t1 - t0) / n, sink & 1);
	return 0;
}
