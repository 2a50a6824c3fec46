/* legacy_rearm itimer|posix RUNS PERIOD_US: a SIGALRM handler that re-arms
 * its own one-shot timer (setitimer, or timer_settime), while main loops
 * over reading it (getitimer, or timer_gettime) until the handler has run
 * RUNS times. Prints the runs, the smallest and largest interval between
 * two runs by CLOCK_MONOTONIC read in the handler, and how often main saw
 * the timer disarmed (between an expiry and its handler) or above its
 * period (never: what is left never exceeds what was set). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

static int posix;
static timer_t timer;
static long long period_ns;
static volatile long long runs, last_ns = -1, min_gap = -1, max_gap;

static long long mono_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void arm(void)
{
	if (posix) {
		struct itimerspec v = { { 0, 0 }, { period_ns / 1000000000LL, period_ns % 1000000000LL } };
		timer_settime(timer, 0, &v, NULL);
	} else {
		struct itimerval v = { { 0, 0 }, { period_ns / 1000000000LL, period_ns % 1000000000LL / 1000 } };
		setitimer(ITIMER_REAL, &v, NULL);
	}
}

/* How much is left of the timer, in ns; -1 when disarmed. */
static long long left(void)
{
	if (posix) {
		struct itimerspec v;
		timer_gettime(timer, &v);
		return v.it_value.tv_sec || v.it_value.tv_nsec ? v.it_value.tv_sec * 1000000000LL + v.it_value.tv_nsec : -1;
	}
	struct itimerval v;
	getitimer(ITIMER_REAL, &v);
	return v.it_value.tv_sec || v.it_value.tv_usec ? v.it_value.tv_sec * 1000000000LL + v.it_value.tv_usec * 1000LL
						       : -1;
}

static void on_alarm(int sig)
{
	(void)sig;
	long long now = mono_ns();
	if (last_ns >= 0) {
		long long gap = now - last_ns;
		if (min_gap < 0 || gap < min_gap)
			min_gap = gap;
		if (gap > max_gap)
			max_gap = gap;
	}
	last_ns = now;
	runs++;
	arm();
}

int main(int argc, char **argv)
{
	if (argc != 4) {
		fprintf(stderr, "usage: legacy_rearm itimer|posix RUNS PERIOD_US\n");
		return 2;
	}
	posix = strcmp(argv[1], "posix") == 0;
	long long want = atoll(argv[2]);
	period_ns = atoll(argv[3]) * 1000LL;
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_alarm;
	sigaction(SIGALRM, &sa, NULL);
	if (posix) {
		struct sigevent sev;
		memset(&sev, 0, sizeof sev);
		sev.sigev_notify = SIGEV_SIGNAL;
		sev.sigev_signo = SIGALRM;
		if (timer_create(CLOCK_MONOTONIC, &sev, &timer) != 0) {
			perror("timer_create");
			return 1;
		}
	}
	long long disarmed = 0, above = 0, reads = 0;
	arm();
	while (runs < want) {
		long long l = left();
		reads++;
		if (l < 0 && runs < want)
			disarmed++;
		if (l > period_ns)
			above++;
	}
	printf("runs=%lld\nmin_gap_ns=%lld\nmax_gap_ns=%lld\nseen_disarmed=%lld\nseen_above=%lld\nreads=%lld\n", runs,
	       min_gap, max_gap, disarmed, above, reads);
	return 0;
}
