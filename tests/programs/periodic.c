/* periodic HZ SECONDS WORK [SCALE]: a periodic control loop as found on robots.
 * Every 1/HZ it does WORK: ROUNDS of work(), or, written "300us", that much
 * CPU time by the kernel's account (work.h: not the CPU-time clock tcs
 * virtualises, so that a test compares tcs's charge with the kernel's).
 * Rounds (from one deadline check to the next, the wait included) that took
 * more CPU than a period by that clock are paused_rounds (for work that
 * fits its period, only a pause of the machine charged as
 * CPU does that), and the deadline misses such CPU can cause, pause_misses:
 * the only misses such a loop may have (its CPU times SCALE, the run's
 * --cpu-scale, when given). Then it sleeps with clock_nanosleep
 * (TIMER_ABSTIME, CLOCK_MONOTONIC) until its next release; a release already
 * past counts as a deadline miss (the loop then runs late, as on hardware);
 * crossed_waits are the waits on time at the check that the CPU of their
 * call (by the kernel's clock) may have made late by the request, and
 * tail_kernel_cpu_ns the CPU from the last wait's return to the end
 * (head_kernel_cpu_ns: from before the first reads to after them);
 * last_wait_kernel_cpu_ns and least_wait_kernel_cpu_ns the CPU of the last
 * wait's call and of the least one, waits_kernel_cpu_ns that of them all,
 * last_round_start_ns when the last round began (the loop's last look at
 * its clock before the end's) and last_round_kernel_cpu_ns the CPU from just
 * before that look to the end (the most a late loop's end can follow it)
 * (unscaled: the kernel's own cost of a sleep, which tcs does not charge,
 * 26 us for a deadline already past on one virtual machine) (the last's excess is a pause of the
 * machine charged as CPU within it: what part of it followed the wake,
 * the loop cannot tell).
 * Stops after SECONDS of its own monotonic clock and prints what it saw,
 * with its CPU-time clock at the end (cpu_ns: all it computed, start
 * included), the CPU its loop used (loop_cpu_ns; and by the kernel's clock,
 * around that, loop_kernel_cpu_ns) and the cores it was seen
 * on after each wait (cores_seen, a bit per core), how often it left its
 * core in the loop (switches), and the stops tcs made of its work
 * (work_stops: voluntary switches while it computed, which makes no wait;
 * the kernel counts a stop's cost as the work's CPU, tcs leaves it out).
 * Any sleep that fails (EINTR included) is counted: there should be none. */
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
	if (argc != 4 && argc != 5) {
		fprintf(stderr, "usage: periodic HZ SECONDS ROUNDS|MICROSECONDSus [CPU_SCALE]\n");
		return 2;
	}
	/* The run's --cpu-scale (or cpu_scale): virtual seconds per CPU second. */
	double scale = argc == 5 ? atof(argv[4]) : 1.0;
	long long period = (long long)(1e9 / atof(argv[1]));
	long long duration = (long long)(atof(argv[2]) * 1e9);
	char *unit;
	unsigned long long rounds = strtoull(argv[3], &unit, 10);
	long long cpu_work = strcmp(unit, "us") == 0 ? (long long)rounds * 1000 : -1;
	long long loop_kernel_cpu = kernel_cpu_ns(), loop_cpu = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	long switches = context_switches();
	long long start = clock_ns(CLOCK_MONOTONIC), next = start, loops = 0, misses = 0, failures = 0, paused_rounds = 0,
		  pause_misses = 0;
	unsigned long long cores_seen = 0;
	/* (A loop with no work makes no system call of its own, which
	 * test_lockstep counts.) */
	const int account = cpu_work > 0 || rounds > 0;
	long long round_start = account ? kernel_cpu_ns() : 0, debt = 0, crossed_waits = 0, woke_kernel = 0;
	long long head_kernel_cpu = account ? (long long)((round_start - loop_kernel_cpu) * scale) : -1;
	long long asked_kernel = 0, last_wait = -1, least_wait = -1, waits_kernel = 0;
	long long last_round_start = -1, last_round_kernel = 0, work_stops = 0;
	for (;;) {
		long long top_kernel = account ? kernel_cpu_ns() : 0, top = clock_ns(CLOCK_MONOTONIC) - start;
		if (top >= duration)
			break;
		last_round_start = top;
		last_round_kernel = top_kernel;
		long before = account ? kernel_thread_voluntary_switches() : 0;
		if (cpu_work >= 0)
			compute_ns(CLOCK_PROCESS_CPUTIME_ID, cpu_work);
		else
			work(rounds);
		if (account)
			work_stops += kernel_thread_voluntary_switches() - before;
		loops++;
		next += period;
		long long checked = clock_ns(CLOCK_MONOTONIC);
		int late = checked > next;
		misses += late;
		if (account) {
			/* The loop is late at a round's check only if the CPU of
			 * the rounds since it was last on time, each from one
			 * check to the next (its wait included: tcs charges the
			 * CPU of the hook before and after the wait, though not
			 * that of a spin in it), exceeds their periods; virtual
			 * time charges no more CPU than the kernel did. So misses
			 * are at most the rounds after which that debt, by the
			 * kernel's clock, is positive: for work that fits its
			 * period, rounds a pause of the machine made longer
			 * (charged as CPU, natively too). */
			long long now = kernel_cpu_ns(), round = (long long)((now - round_start) * scale);
			round_start = now;
			debt = debt + round - period > 0 ? debt + round - period : 0;
			if (debt > 0) {
				pause_misses++;
				paused_rounds += round > period;
			}
		}
		struct timespec ts = { next / 1000000000LL, next % 1000000000LL };
		if (account)
			asked_kernel = kernel_cpu_ns();
		int r = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
		if (account) {
			woke_kernel = kernel_cpu_ns();
			waits_kernel += woke_kernel - asked_kernel;
			last_wait = (long long)((woke_kernel - asked_kernel) * scale);
			least_wait = least_wait < 0 || last_wait < least_wait ? last_wait : least_wait;
		}
		if (r != 0)
			failures++;
		/* The wait itself may be asked for after its deadline though the
		 * check before it was on time (tcs counts a miss where the
		 * request is late): only if the CPU of the call, by the
		 * kernel's clock, can span what was left of the period. */
		if (account && !late && checked + (long long)((woke_kernel - round_start) * scale) > next)
			crossed_waits++;
		int core = sched_getcpu();
		if (core >= 0 && core < 64)
			cores_seen |= 1ull << core;
	}
	double elapsed = (clock_ns(CLOCK_MONOTONIC) - start) / 1e9;
	loop_cpu = clock_ns(CLOCK_PROCESS_CPUTIME_ID) - loop_cpu;
	long long end_kernel = kernel_cpu_ns();
	loop_kernel_cpu = end_kernel - loop_kernel_cpu;
	/* The CPU from the last wait's return to here (times SCALE), which is
	 * all that may follow the last release in elapsed_s (-1: a loop with
	 * no work does not read it). */
	long long tail_kernel_cpu = account ? (long long)((end_kernel - woke_kernel) * scale) : -1;
	last_round_kernel = account ? (long long)((end_kernel - last_round_kernel) * scale) : -1;
	switches = context_switches() - switches;
	printf("asked_hz=%s\nloops=%lld\nelapsed_s=%.9f\nrate_hz=%.3f\nmisses=%lld\nsleep_failures=%lld\nloop_cpu_ns=%lld\ncpu_ns=%lld\n"
	       "loop_kernel_cpu_ns=%lld\ncores_seen=%llu\nswitches=%ld\npaused_rounds=%lld\npause_misses=%lld\ncrossed_waits=%lld\n"
	       "head_kernel_cpu_ns=%lld\ntail_kernel_cpu_ns=%lld\nlast_wait_kernel_cpu_ns=%lld\nleast_wait_kernel_cpu_ns=%lld\n"
	       "waits_kernel_cpu_ns=%lld\nlast_round_start_ns=%lld\nlast_round_kernel_cpu_ns=%lld\nwork_stops=%lld\n",
	       argv[1], loops, elapsed, loops / elapsed, misses, failures, loop_cpu, clock_ns(CLOCK_PROCESS_CPUTIME_ID), loop_kernel_cpu, cores_seen,
	       switches, paused_rounds, pause_misses, crossed_waits, head_kernel_cpu, tail_kernel_cpu, last_wait, least_wait,
	       account ? waits_kernel : -1, last_round_start, last_round_kernel, work_stops);
	return 0;
}
