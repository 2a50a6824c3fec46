/* periodic HZ SECONDS WORK: a periodic control loop as found on robots.
 * Every 1/HZ it does WORK: ROUNDS of work(), or, written "300us", that much
 * of its own CPU time (the process CPU-time clock, which tcs virtualises:
 * so the work costs exactly that much virtual CPU). Then it sleeps with clock_nanosleep
 * (TIMER_ABSTIME, CLOCK_MONOTONIC) until its next release; a release already
 * past counts as a deadline miss (the loop then runs late, as on hardware).
 * Stops after SECONDS of its own monotonic clock and prints what it saw,
 * with its CPU-time clock at the end (cpu_ns: all it computed, start
 * included), the CPU its loop used (loop_cpu_ns) and the cores it was seen
 * on after each wait (cores_seen, a bit per core), and how often it left its
 * core in the loop (switches).
 * Any sleep that fails (EINTR included) is counted: there should be none. */
#define _GNU_SOURCE
#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "work.h"

/* How often this process has left its core (context switches, voluntary
 * or not): a wait answered through the channel is at least one. */
static long context_switches(void)
{
	struct rusage ru;
	return getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_nvcsw + ru.ru_nivcsw : -1;
}

int main(int argc, char **argv)
{
	if (argc != 4) {
		fprintf(stderr, "usage: periodic HZ SECONDS ROUNDS|MICROSECONDSus\n");
		return 2;
	}
	long long period = (long long)(1e9 / atof(argv[1]));
	long long duration = (long long)(atof(argv[2]) * 1e9);
	char *unit;
	unsigned long long rounds = strtoull(argv[3], &unit, 10);
	long long cpu_work = strcmp(unit, "us") == 0 ? (long long)rounds * 1000 : -1;
	long long loop_cpu = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	long switches = context_switches();
	long long start = clock_ns(CLOCK_MONOTONIC), next = start, loops = 0, misses = 0, failures = 0;
	unsigned long long cores_seen = 0;
	while (clock_ns(CLOCK_MONOTONIC) - start < duration) {
		if (cpu_work >= 0) {
			long long c0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
			while (clock_ns(CLOCK_PROCESS_CPUTIME_ID) - c0 < cpu_work)
				work(100);
		} else {
			work(rounds);
		}
		loops++;
		next += period;
		if (clock_ns(CLOCK_MONOTONIC) > next)
			misses++;
		struct timespec ts = { next / 1000000000LL, next % 1000000000LL };
		int r = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
		if (r != 0)
			failures++;
		int core = sched_getcpu();
		if (core >= 0 && core < 64)
			cores_seen |= 1ull << core;
	}
	double elapsed = (clock_ns(CLOCK_MONOTONIC) - start) / 1e9;
	loop_cpu = clock_ns(CLOCK_PROCESS_CPUTIME_ID) - loop_cpu;
	switches = context_switches() - switches;
	printf("loops=%lld\nelapsed_s=%.9f\nrate_hz=%.3f\nmisses=%lld\nsleep_failures=%lld\nloop_cpu_ns=%lld\ncpu_ns=%lld\n"
	       "cores_seen=%llu\nswitches=%ld\n",
	       loops, elapsed, loops / elapsed, misses, failures, loop_cpu, clock_ns(CLOCK_PROCESS_CPUTIME_ID), cores_seen,
	       switches);
	return 0;
}
