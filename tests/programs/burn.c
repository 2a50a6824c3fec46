/* burn ROUNDS [NAME]: does ROUNDS of work() once and prints, as key=value
 * lines in one write (after name=NAME, when given), the elapsed time of its
 * monotonic clock and of its process and thread CPU-time clocks (ns), the
 * CPU the kernel charged it meanwhile, read around all three and inside
 * them, the voluntary context switches meanwhile (each stop tcs made is
 * one), and the core it ended on. */
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "work.h"

int main(int argc, char **argv)
{
	if (argc != 2 && argc != 3) {
		fprintf(stderr, "usage: burn ROUNDS [NAME]\n");
		return 2;
	}
	unsigned long long rounds = strtoull(argv[1], NULL, 10);
	/* Each clock read once before: the first call of a function binds it
	 * (the dynamic linker's work, tens of microseconds), which is not the
	 * reads' own cost. */
	clock_ns(CLOCK_MONOTONIC);
	clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	clock_ns(CLOCK_THREAD_CPUTIME_ID);
	/* The kernel's CPU read outside the virtual clocks' span and inside it:
	 * a pause of the machine between two reads is then on the right side
	 * of each bound. */
	long s0 = kernel_voluntary_switches();
	long long k0 = kernel_cpu_ns();
	long long m0 = clock_ns(CLOCK_MONOTONIC), c0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	long long t0 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
	long long i0 = kernel_cpu_ns();
	work(rounds);
	long long i1 = kernel_cpu_ns();
	long long t1 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
	long long m1 = clock_ns(CLOCK_MONOTONIC), c1 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	long long k1 = kernel_cpu_ns();
	long s1 = kernel_voluntary_switches();
	if (argc == 3)
		printf("name=%s\n", argv[2]);
	printf("monotonic_ns=%lld\ncpu_ns=%lld\nthread_cpu_ns=%lld\nkernel_cpu_ns=%lld\nkernel_inner_cpu_ns=%lld\n"
	       "voluntary_switches=%ld\ncore=%d\n",
	       m1 - m0, c1 - c0, t1 - t0, k1 - k0, i1 - i0, s1 - s0, sched_getcpu());
	return 0;
}
