/* alarm_loop MODE N PERIOD_US WORK_US: a legacy loop paced by a signal.
 * MODE: itimer (setitimer ITIMER_REAL, SIGALRM), posix (timer_create with
 * SIGEV_SIGNAL, SIGRTMIN), thread (SIGEV_THREAD_ID to the main thread), each
 * periodic, waited for with sigsuspend, doing WORK_US of its own CPU time
 * per tick; or alarm (alarm(1) and pause, N times). Prints, as key=value
 * lines, the ticks handled, the monotonic time the loop took, what the
 * timer said was left right after arming, and how long sleep(5) slept when
 * an alarm(1) interrupted it. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include "work.h"

static volatile sig_atomic_t ticks;

static void on_tick(int sig)
{
	(void)sig;
	ticks++;
}

int main(int argc, char **argv)
{
	if (argc != 5) {
		fprintf(stderr, "usage: alarm_loop itimer|posix|thread|alarm N PERIOD_US WORK_US\n");
		return 2;
	}
	const char *mode = argv[1];
	long n = atol(argv[2]);
	long long period = atoll(argv[3]) * 1000LL, work_ns = atoll(argv[4]) * 1000LL;
	int sig = strcmp(mode, "posix") == 0 || strcmp(mode, "thread") == 0 ? SIGRTMIN : SIGALRM;
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_tick;
	sigaction(sig, &sa, NULL);
	sigset_t block, empty;
	sigemptyset(&block);
	sigaddset(&block, sig);
	sigemptyset(&empty);
	long long left = -1;
	timer_t posix = 0;
	long long start = clock_ns(CLOCK_MONOTONIC);
	long long cpu_start = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	if (strcmp(mode, "alarm") == 0) {
		for (long i = 0; i < n; i++) {
			alarm(1);
			pause();
		}
	} else {
		sigprocmask(SIG_BLOCK, &block, NULL);
		struct timespec p = { period / 1000000000, period % 1000000000 };
		if (strcmp(mode, "itimer") == 0) {
			struct itimerval it = { { p.tv_sec, p.tv_nsec / 1000 }, { p.tv_sec, p.tv_nsec / 1000 } }, cur;
			setitimer(ITIMER_REAL, &it, NULL);
			getitimer(ITIMER_REAL, &cur);
			left = cur.it_value.tv_sec * 1000000000LL + cur.it_value.tv_usec * 1000LL;
		} else {
			struct sigevent sev;
			memset(&sev, 0, sizeof sev);
			sev.sigev_signo = sig;
			sev.sigev_notify = SIGEV_SIGNAL;
			if (strcmp(mode, "thread") == 0) {
				sev.sigev_notify = SIGEV_THREAD_ID;
				sev._sigev_un._tid = (pid_t)syscall(SYS_gettid);
			}
			timer_t t = 0;
			struct itimerspec its = { p, p }, cur;
			if (timer_create(CLOCK_MONOTONIC, &sev, &t) != 0 || timer_settime(t, 0, &its, NULL) != 0) {
				perror("timer");
				return 1;
			}
			timer_gettime(t, &cur);
			left = cur.it_value.tv_sec * 1000000000LL + cur.it_value.tv_nsec;
			posix = t;
		}
		while (ticks < n) {
			long long c0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
			while (clock_ns(CLOCK_PROCESS_CPUTIME_ID) - c0 < work_ns)
				work(100);
			sigsuspend(&empty);
		}
		struct itimerval off = { { 0, 0 }, { 0, 0 } };
		setitimer(ITIMER_REAL, &off, NULL);
		if (posix)
			timer_delete(posix);
		sigprocmask(SIG_UNBLOCK, &block, NULL);
	}
	long long took = clock_ns(CLOCK_MONOTONIC) - start;
	long long took_cpu = clock_ns(CLOCK_PROCESS_CPUTIME_ID) - cpu_start;
	long handled = ticks;
	/* alarm(1) interrupts sleep(5): it returns the 4 s it did not sleep. */
	signal(SIGALRM, on_tick);
	long long s0 = clock_ns(CLOCK_MONOTONIC);
	alarm(1);
	unsigned unslept = sleep(5);
	long long slept = clock_ns(CLOCK_MONOTONIC) - s0;
	printf("ticks=%ld\nloop_ns=%lld\nloop_cpu_ns=%lld\nleft_ns=%lld\nunslept=%u\nslept_ns=%lld\n", handled, took,
	       took_cpu, left, unslept, slept);
	return 0;
}
