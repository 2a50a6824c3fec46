/* notify_timer N PERIOD_US [CALLBACK_WORK_US]: a periodic timer_create
 * timer with SIGEV_THREAD, whose function does CALLBACK_WORK_US of CPU time,
 * while the main thread sleeps N periods and a half; then the timer is
 * deleted and the program sleeps 5 periods more. Prints, as key=value
 * lines: the calls, the expiries they stand for (1 + timer_getoverrun
 * each), when the first came after arming, how late the latest expiry a
 * call stood for was at most, the calls after timer_delete, and whether the
 * function ran on a thread other than main. */
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
static pthread_t main_thread;
static volatile int other_thread = 1;

static void on_expiry(union sigval v)
{
	long long now = clock_ns(CLOCK_MONOTONIC);
	if (v.sival_int != 42 || pthread_equal(pthread_self(), main_thread))
		other_thread = 0;
	expiries += 1 + timer_getoverrun(timer);
	long long late = now - (start + expiries * period);
	if (late > max_late_ns)
		max_late_ns = late;
	if (first_ns < 0)
		first_ns = now - start;
	last_ns = now - start;
	calls++;
	compute_ns(CLOCK_THREAD_CPUTIME_ID, work_ns);
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
	sleep_ns(n * period + period / 2);
	timer_delete(timer);
	long before = calls;
	sleep_ns(5 * period);
	printf("calls=%ld\nexpiries=%ld\nfirst_ns=%lld\nlast_ns=%lld\nmax_late_ns=%lld\nafter_delete=%ld\nother_thread=%d\n",
	       before, expiries, first_ns, last_ns, max_late_ns, calls - before, other_thread);
	return 0;
}
