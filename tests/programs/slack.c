/* slack: how long timed waits take, for the timer slack's contract
 * (docs/DESIGN.md §2). Prints key=value lines, each a span of
 * CLOCK_MONOTONIC in ns: 100 relative 1 ms sleeps (each ends its slack
 * late: they add up), 100 absolute ones 1 ms apart (only the last one's
 * shows), the same relative sleeps after prctl(PR_SET_TIMERSLACK, 1 us)
 * and the slack prctl reports, in a thread created real-time and in the
 * main thread made real-time (none), back to normal (50 us again), a 1 s
 * poll timeout (0.1 % of it: 1 ms) and a 2 ms pthread_cond_timedwait. */
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <sys/prctl.h>
#include <time.h>

#define MS 1000000LL

static long long mono(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec * 1000000000LL + t.tv_nsec;
}

static long long relative_sleeps(void)
{
	long long t0 = mono();
	for (int i = 0; i < 100; i++) {
		struct timespec d = { 0, MS };
		nanosleep(&d, NULL);
	}
	return mono() - t0;
}

static long long absolute_sleeps(void)
{
	long long t0 = mono(), next = t0;
	for (int i = 0; i < 100; i++) {
		next += MS;
		struct timespec d = { next / 1000000000LL, next % 1000000000LL };
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &d, NULL);
	}
	return mono() - t0;
}

static void *rt_thread(void *out)
{
	*(long long *)out = relative_sleeps();
	return NULL;
}

int main(void)
{
	printf("relative_ns=%lld\n", relative_sleeps());
	printf("absolute_ns=%lld\n", absolute_sleeps());
	printf("default_slack_ns=%d\n", prctl(PR_GET_TIMERSLACK));
	prctl(PR_SET_TIMERSLACK, 1000UL);
	printf("set_slack_ns=%d\n", prctl(PR_GET_TIMERSLACK));
	printf("relative_1us_ns=%lld\n", relative_sleeps());
	prctl(PR_SET_TIMERSLACK, 0UL); /* back to the one it started with */
	printf("reset_slack_ns=%d\n", prctl(PR_GET_TIMERSLACK));

	pthread_attr_t attr;
	pthread_attr_init(&attr);
	pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
	pthread_attr_setschedpolicy(&attr, SCHED_FIFO);
	struct sched_param sp = { .sched_priority = 1 };
	pthread_attr_setschedparam(&attr, &sp);
	long long rt_span = -1;
	pthread_t t;
	if (pthread_create(&t, &attr, rt_thread, &rt_span) == 0)
		pthread_join(t, NULL);
	printf("rt_thread_relative_ns=%lld\n", rt_span);

	if (sched_setscheduler(0, SCHED_FIFO, &sp) == 0) {
		printf("rt_main_relative_ns=%lld\n", relative_sleeps());
		sp.sched_priority = 0;
		sched_setscheduler(0, SCHED_OTHER, &sp);
	}
	printf("normal_again_relative_ns=%lld\n", relative_sleeps());

	long long t0 = mono();
	poll(NULL, 0, 1000);
	printf("poll_1s_ns=%lld\n", mono() - t0);

	pthread_mutex_t m = PTHREAD_MUTEX_INITIALIZER;
	pthread_cond_t c = PTHREAD_COND_INITIALIZER;
	struct timespec until;
	clock_gettime(CLOCK_REALTIME, &until);
	until.tv_nsec += 2 * MS;
	if (until.tv_nsec >= 1000000000L) {
		until.tv_sec++;
		until.tv_nsec -= 1000000000L;
	}
	pthread_mutex_lock(&m);
	t0 = mono();
	pthread_cond_timedwait(&c, &m, &until);
	printf("cond_2ms_ns=%lld\n", mono() - t0);
	pthread_mutex_unlock(&m);
	return 0;
}
