/* periodic_controller: the shape of most robot control loops, in plain C
 * that knows nothing of tcs. Every period it does a fixed computation of
 * --work thousand rounds (standing for a control law: the same work takes
 * longer on a slower CPU), then sleeps until its
 * next release with clock_nanosleep(TIMER_ABSTIME). When it stops (end of
 * --seconds, or SIGTERM/SIGINT, as tcs-run sends at the end of a run) it
 * prints what it saw: loop rate, deadline misses, worst lateness.
 *
 *   periodic_controller [--rate HZ] [--work K] [--seconds S]
 *   tcs-run -d 5s -- periodic_controller --rate 1000 --work 150
 *   tcs-run -d 5s --cpu-scale 8 -- periodic_controller --work 150   (an 8x slower CPU: misses) */
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static volatile sig_atomic_t stop;

static void on_signal(int sig)
{
	(void)sig;
	stop = 1;
}

static long long now_ns(clockid_t clock)
{
	struct timespec ts;
	clock_gettime(clock, &ts);
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

/* The control law's stand-in: K thousand rounds of integer arithmetic. */
static void compute(long k)
{
	static volatile unsigned long long sink;
	unsigned long long x = sink + 88172645463325252ull;
	for (long i = 0; i < k * 1000; i++) {
		x ^= x << 13;
		x ^= x >> 7;
		x ^= x << 17;
	}
	sink = x;
}

int main(int argc, char **argv)
{
	double rate = 1000, seconds = 0;
	long work = 150;
	static const struct option opts[] = {
		{ "rate", required_argument, NULL, 'r' },
		{ "work", required_argument, NULL, 'w' },
		{ "seconds", required_argument, NULL, 's' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	int c;
	while ((c = getopt_long(argc, argv, "r:w:s:h", opts, NULL)) != -1) {
		switch (c) {
		case 'r':
			rate = atof(optarg);
			break;
		case 'w':
			work = atol(optarg);
			break;
		case 's':
			seconds = atof(optarg);
			break;
		default:
			fprintf(stderr, "usage: %s [--rate HZ] [--work K] [--seconds S]\n", argv[0]);
			return c == 'h' ? 0 : 2;
		}
	}
	if (rate <= 0 || work < 0) {
		fprintf(stderr, "%s: --rate must be positive and --work not negative\n", argv[0]);
		return 2;
	}
	signal(SIGTERM, on_signal);
	signal(SIGINT, on_signal);

	const long long period = (long long)(1e9 / rate);
	long long start = now_ns(CLOCK_MONOTONIC), next = start;
	long long cycles = 0, misses = 0, worst_late = 0, cpu_start = now_ns(CLOCK_PROCESS_CPUTIME_ID);
	while (!stop && (seconds <= 0 || now_ns(CLOCK_MONOTONIC) - start < (long long)(seconds * 1e9))) {
		compute(work);
		cycles++;
		next += period;
		long long late = now_ns(CLOCK_MONOTONIC) - next;
		if (late > 0) {
			misses++;
			if (late > worst_late)
				worst_late = late;
		}
		struct timespec ts = { next / 1000000000LL, next % 1000000000LL };
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
	}
	double elapsed = (now_ns(CLOCK_MONOTONIC) - start) / 1e9;
	double cpu_per_cycle = cycles ? (now_ns(CLOCK_PROCESS_CPUTIME_ID) - cpu_start) / 1e3 / cycles : 0;
	printf("periodic_controller: %lld cycles in %.3f s: %.1f Hz (asked for %.1f Hz), %lld deadline misses, "
	       "worst lateness %.3f ms, %.0f us of CPU per cycle\n",
	       cycles, elapsed, elapsed > 0 ? cycles / elapsed : 0, rate, misses, worst_late / 1e6, cpu_per_cycle);
	return 0;
}
