/* compute SECONDS...: computes each SECONDS of CPU in turn, by the
 * kernel's clock (work.h: a raw system call tcs does not see, so it is no
 * wait and no clock read of the program's), with a 1 ms sleep between
 * two: a program that computes long without waiting, for lockstep's
 * warning (tcs-run(1), LIMITATIONS). Prints the CPU each took
 * (cpu_ns_N). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "work.h"

int main(int argc, char **argv)
{
	for (int i = 1; i < argc; i++) {
		if (i > 1) {
			struct timespec d = { 0, 1000000 };
			nanosleep(&d, NULL);
		}
		long long ns = (long long)(atof(argv[i]) * 1e9);
		printf("cpu_ns_%d=%lld\n", i, compute_ns(CLOCK_PROCESS_CPUTIME_ID, ns));
	}
	return 0;
}
