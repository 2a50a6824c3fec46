/* legacy_fork_threads FORKS: fork from a threaded program. Two threads keep
 * calling timer_settime, getitimer and clock_gettime (hooks that may be
 * mid-call at the fork); main forks FORKS children one after another, each
 * of which calls setitimer, nanosleep (1 ms) and clock_gettime and _exits
 * with 0 if its sleep did not end early. Every third child forks a
 * grandchild that does the same. Prints the children reaped and how many
 * failed. */
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static volatile int stop;

static long long mono_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void *busy(void *arg)
{
	timer_t t;
	struct sigevent sev;
	memset(&sev, 0, sizeof sev);
	sev.sigev_notify = SIGEV_NONE;
	timer_create(CLOCK_MONOTONIC, &sev, &t);
	long n = 0;
	while (!stop) {
		struct itimerspec v = { { 0, 0 }, { 1, (long)arg } };
		timer_settime(t, 0, &v, NULL);
		struct itimerval cur;
		getitimer(ITIMER_REAL, &cur);
		(void)mono_ns();
		if (++n % 64 == 0)
			sched_yield();
	}
	timer_delete(t);
	return NULL;
}

/* What a forked child does: 0 if all went as it should. */
static int child_work(void)
{
	struct itimerval v = { { 0, 0 }, { 5, 0 } };
	if (setitimer(ITIMER_REAL, &v, NULL) != 0)
		return 3;
	long long start = mono_ns();
	struct timespec ms = { 0, 1000000 };
	nanosleep(&ms, NULL);
	if (mono_ns() - start < 1000000)
		return 4;
	struct itimerval off = { { 0, 0 }, { 0, 0 } };
	setitimer(ITIMER_REAL, &off, NULL);
	return 0;
}

static int reap(pid_t pid)
{
	int status;
	if (waitpid(pid, &status, 0) != pid)
		return 5;
	return WIFEXITED(status) ? WEXITSTATUS(status) : 6;
}

int main(int argc, char **argv)
{
	int forks = argc > 1 ? atoi(argv[1]) : 20;
	pthread_t a, b;
	pthread_create(&a, NULL, busy, (void *)1000L);
	pthread_create(&b, NULL, busy, (void *)2000L);
	int reaped = 0, failed = 0;
	for (int i = 0; i < forks; i++) {
		pid_t pid = fork();
		if (pid < 0) {
			perror("fork");
			failed++;
			continue;
		}
		if (pid == 0) {
			int r = child_work();
			if (r == 0 && i % 3 == 0) {
				pid_t g = fork();
				if (g == 0)
					_exit(child_work());
				r = g < 0 ? 7 : reap(g);
			}
			_exit(r);
		}
		int r = reap(pid);
		reaped++;
		if (r != 0) {
			fprintf(stderr, "legacy_fork_threads: child %d ended %d\n", i, r);
			failed++;
		}
	}
	stop = 1;
	pthread_join(a, NULL);
	pthread_join(b, NULL);
	printf("reaped=%d\nfailed=%d\n", reaped, failed);
	return failed != 0;
}
