/* burn ROUNDS: does ROUNDS of work() once and prints, as key=value lines,
 * the elapsed time of its monotonic clock and of its CPU-time clock (ns). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "work.h"

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: burn ROUNDS\n");
		return 2;
	}
	unsigned long long rounds = strtoull(argv[1], NULL, 10);
	long long m0 = clock_ns(CLOCK_MONOTONIC), c0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	work(rounds);
	long long m1 = clock_ns(CLOCK_MONOTONIC), c1 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	printf("monotonic_ns=%lld\ncpu_ns=%lld\n", m1 - m0, c1 - c0);
	return 0;
}
