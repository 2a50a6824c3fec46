/* legacy_handler_calls RUNS: handlers that call hooked functions while main
 * is inside others. A POSIX timer's SIGALRM handler re-arms it with
 * timer_settime and sleeps 100 us with nanosleep; a second POSIX timer's
 * SIGUSR1 handler reads clock_gettime and arms ITIMER_REAL with setitimer
 * (whose SIGALRM runs the first handler once more).
 * Main loops over timer_gettime, getitimer and clock_gettime, with a
 * nanosleep of 200 us every 16th round, until each handler has run RUNS
 * times. Checks that no sleep ended early (by CLOCK_MONOTONIC around it,
 * restarted with what was left after EINTR, as real code does) and prints
 * the runs, the sleeps and how many ended early. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

static timer_t posix_alarm, posix_usr1;
static volatile long long alarm_runs, usr1_runs, early, sleeps, interrupted;

static long long mono_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

/* Sleeps ns whole, restarting after a handler, and checks it by the clock. */
static void sleep_whole(long long ns)
{
	long long start = mono_ns();
	struct timespec want = { 0, ns }, left;
	while (nanosleep(&want, &left) != 0 && errno == EINTR) {
		interrupted++;
		want = left;
	}
	if (mono_ns() - start < ns)
		early++;
	sleeps++;
}

static void on_alarm(int sig)
{
	(void)sig;
	int saved = errno;
	alarm_runs++;
	struct itimerspec again = { { 0, 0 }, { 0, 700000 } };
	timer_settime(posix_alarm, 0, &again, NULL);
	sleep_whole(100000);
	errno = saved;
}

static void on_usr1(int sig)
{
	(void)sig;
	usr1_runs++;
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	struct itimerval v = { { 0, 0 }, { 0, 900 } };
	setitimer(ITIMER_REAL, &v, NULL);
}

int main(int argc, char **argv)
{
	long long want = argc > 1 ? atoll(argv[1]) : 100;
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_alarm;
	sigaction(SIGALRM, &sa, NULL);
	sa.sa_handler = on_usr1;
	sigaction(SIGUSR1, &sa, NULL);
	struct sigevent sev;
	memset(&sev, 0, sizeof sev);
	sev.sigev_notify = SIGEV_SIGNAL;
	sev.sigev_signo = SIGALRM;
	timer_create(CLOCK_MONOTONIC, &sev, &posix_alarm);
	sev.sigev_signo = SIGUSR1;
	timer_create(CLOCK_MONOTONIC, &sev, &posix_usr1);
	struct itimerspec first = { { 0, 0 }, { 0, 700000 } };
	timer_settime(posix_alarm, 0, &first, NULL);
	struct itimerspec every = { { 0, 1300000 }, { 0, 1300000 } };
	timer_settime(posix_usr1, 0, &every, NULL);
	long long rounds = 0;
	while (alarm_runs < want || usr1_runs < want) {
		struct itimerspec cur;
		struct itimerval real;
		struct timespec ts;
		timer_gettime(posix_alarm, &cur);
		getitimer(ITIMER_REAL, &real);
		clock_gettime(CLOCK_MONOTONIC, &ts);
		if (++rounds % 16 == 0)
			sleep_whole(200000);
	}
	struct itimerspec off = { { 0, 0 }, { 0, 0 } };
	timer_settime(posix_alarm, 0, &off, NULL);
	timer_settime(posix_usr1, 0, &off, NULL);
	struct itimerval real_off = { { 0, 0 }, { 0, 0 } };
	setitimer(ITIMER_REAL, &real_off, NULL);
	printf("alarm_runs=%lld\nusr1_runs=%lld\nsleeps=%lld\nearly=%lld\ninterrupted=%lld\n", alarm_runs, usr1_runs,
	       sleeps, early, interrupted);
	return early != 0;
}
