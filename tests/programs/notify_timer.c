/* notify_timer N PERIOD_US [CALLBACK_WORK_US]: a periodic timer_create
 * timer with SIGEV_THREAD, whose function does CALLBACK_WORK_US of CPU time,
 * while the main thread sleeps N periods and a half; then the timer is
 * deleted and the program sleeps 5 periods more. Prints, as key=value
 * lines: the calls, the expiries they stand for (1 + timer_getoverrun
 * each), when the first came after arming, how late the latest expiry a
 * call stood for was at most, the calls after timer_delete, and whether the
 * function ran on a thread other than main. Monotonic from just before the
 * arming: armed_ns (just after it), woke_ns (main's sleep over, just before
 * timer_delete) and deleted_ns (just after it). And the evidence of the
 * process's CPU by the kernel's clock (work.h), each call's from its start
 * to the next's (a round): calls_kernel_ns, from the first call's start to
 * the last's; round_max_ns, the longest round; tail_kernel_ns,
 * from the last call's start to main's waking; pause_overruns, the
 * expiries rounds that long may have folded into an overrun (see
 * on_expiry); work_stops_before_last, the stops tcs made of the calls'
 * work before the last call (their cost, counted by the kernel as the
 * work's CPU, tcs leaves out). Each CPU span is read just outside the
 * clock reads it goes with, so that all of the span is in it. */
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "work.h"

static timer_t timer;
static long long start, period, work_ns;
static volatile long calls, expiries;
static volatile long long first_ns = -1, max_late_ns, last_ns;
/* Stops tcs made of the function's work (its thread's voluntary switches
 * while it computed: the work makes no wait), all of them and those
 * before the last call. */
static volatile long work_stops, stops_before_last;
static pthread_t main_thread;
static volatile int other_thread = 1;
static volatile long long first_kernel, last_kernel, last_kernel_after, round_max, pause_overruns;

/* How far the helper's look at the clock, which decides a call's overrun,
 * may come before the call's first reading: the helper's unlock and the
 * call between them, less than a clock read costs (under 25 us); and 20 us
 * an estimated read may run ahead (libtcs_preload/cpu_estimate.c). */
#define LOOK_SLACK_NS 45000LL

static void on_expiry(union sigval v)
{
	long long kernel = kernel_cpu_ns(), now = clock_ns(CLOCK_MONOTONIC);
	last_kernel_after = kernel_cpu_ns();
	if (calls > 0) {
		/* Virtual time passes by the process's CPU (or waits till an
		 * expiry). A call's overrun is the expiries that passed since
		 * the one its predecessor stood for, less one: those that came
		 * while the helper computed, which its predecessor's round (by
		 * the kernel's CPU, which tcs charges no more than, and the
		 * helper's look up to LOOK_SLACK_NS before the round's first
		 * reading) can hold at most (round + slack) / period of. For a
		 * function that fits its period, only a pause of the machine
		 * (charged as CPU) makes a round that long. */
		long long round = kernel - last_kernel;
		if (round > round_max)
			round_max = round;
		pause_overruns += (round + LOOK_SLACK_NS) / period;
	} else {
		first_kernel = kernel;
	}
	last_kernel = kernel;
	if (v.sival_int != 42 || pthread_equal(pthread_self(), main_thread))
		other_thread = 0;
	expiries += 1 + timer_getoverrun(timer);
	long long late = now - (start + expiries * period);
	if (late > max_late_ns)
		max_late_ns = late;
	if (first_ns < 0)
		first_ns = now - start;
	last_ns = now - start;
	stops_before_last = work_stops;
	calls++;
	long before = kernel_thread_voluntary_switches();
	compute_ns(CLOCK_THREAD_CPUTIME_ID, work_ns);
	work_stops += kernel_thread_voluntary_switches() - before;
}

static void sleep_ns(long long ns)
{
	struct timespec ts = { ns / 1000000000, ns % 1000000000 };
	while (nanosleep(&ts, &ts) != 0)
		;
}

int main(int argc, char **argv)
{
	if (argc != 3 && argc != 4) {
		fprintf(stderr, "usage: notify_timer N PERIOD_US [CALLBACK_WORK_US]\n");
		return 2;
	}
	long n = atol(argv[1]);
	period = atoll(argv[2]) * 1000LL;
	work_ns = argc == 4 ? atoll(argv[3]) * 1000LL : 0;
	main_thread = pthread_self();
	struct sigevent sev;
	memset(&sev, 0, sizeof sev);
	sev.sigev_notify = SIGEV_THREAD;
	sev.sigev_notify_function = on_expiry;
	sev.sigev_value.sival_int = 42;
	struct timespec p = { period / 1000000000, period % 1000000000 };
	struct itimerspec its = { p, p };
	if (timer_create(CLOCK_MONOTONIC, &sev, &timer) != 0) {
		perror("timer_create");
		return 1;
	}
	start = clock_ns(CLOCK_MONOTONIC);
	if (timer_settime(timer, 0, &its, NULL) != 0) {
		perror("timer_settime");
		return 1;
	}
	long long armed = clock_ns(CLOCK_MONOTONIC) - start;
	sleep_ns(n * period + period / 2);
	long long woke = clock_ns(CLOCK_MONOTONIC) - start, tail = kernel_cpu_ns() - last_kernel;
	timer_delete(timer);
	long long deleted = clock_ns(CLOCK_MONOTONIC) - start;
	long before = calls;
	sleep_ns(5 * period);
	printf("calls=%ld\nexpiries=%ld\nfirst_ns=%lld\nlast_ns=%lld\nmax_late_ns=%lld\nafter_delete=%ld\nother_thread=%d\n",
	       before, expiries, first_ns, last_ns, max_late_ns, calls - before, other_thread);
	printf("armed_ns=%lld\nwoke_ns=%lld\ndeleted_ns=%lld\ncalls_kernel_ns=%lld\nround_max_ns=%lld\ntail_kernel_ns=%lld\n"
	       "pause_overruns=%lld\nwork_stops_before_last=%ld\n",
	       armed, woke, deleted, last_kernel_after - first_kernel, round_max, tail, pause_overruns, stops_before_last);
	return 0;
}
