/* sleep_roundtrip [N]: wall nanoseconds per nanosleep(1 us). Under tcs-run
 * in lockstep mode that is one round trip to the coordinator: the program
 * asks to wait, the coordinator advances virtual time and wakes it. */
#include <stdio.h>
#include <stdlib.h>

#include "bench_time.h"

int main(int argc, char **argv)
{
	long n = argc > 1 ? atol(argv[1]) : 100000;
	struct timespec req = { 0, 1000 };
	double t0 = bench_wall_ns();
	for (long i = 0; i < n; i++)
		nanosleep(&req, NULL);
	double t1 = bench_wall_ns();
	printf("sleep_roundtrip_ns=%.0f\n", (t1 - t0) / n);
	return 0;
}
