/* alarm_loop MODE N PERIOD_US WORK_US: a legacy loop paced by a signal.
 * MODE: itimer (setitimer ITIMER_REAL, SIGALRM), posix (timer_create with
 * SIGEV_SIGNAL, SIGRTMIN), thread (SIGEV_THREAD_ID to the main thread), each
 * periodic, waited for with sigsuspend, doing WORK_US of CPU time per tick
 * (by the kernel's clock: work.h); or alarm (alarm(1) and pause, N times).
 * Prints, as key=value lines, the ticks handled, the monotonic time the
 * loop took with its CPU read outside and inside that span and the
 * kernel's CPU around it (and from just before the timer was armed to just after the
 * last tick: ticked_ns, with the CPU the kernel charged from just before
 * that first read to the arming call's return, head_kernel_ns, and from
 * the last wait's call to that last read, tail_kernel_ns), what the timer
 * said was left right after arming, how long sleep(5) slept when an
 * alarm(1) interrupted it, and how many ticks rounds (from one sigsuspend
 * to the next) that took longer than a period by the kernel's clock may
 * have lost (pause_ticks: for work that fits its period, only a pause of
 * the machine does that). */
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
	long long left = -1, pause_ticks = 0, armed_at = 0, ticked = -1, head_kernel = 0, tail_kernel = 0, last_wait = 0;
	timer_t posix = 0;
	/* The loop's CPU read outside its monotonic span and inside it (so a
	 * pause between two reads is on the right side of each bound), and by
	 * the kernel's clock around all of them. */
	long switches_start = kernel_voluntary_switches();
	long long kernel_start = kernel_cpu_ns(), cpu_start = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	long long start = clock_ns(CLOCK_MONOTONIC), inner_start = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
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
			head_kernel = kernel_cpu_ns();
			armed_at = clock_ns(CLOCK_MONOTONIC);
			setitimer(ITIMER_REAL, &it, NULL);
			head_kernel = kernel_cpu_ns() - head_kernel;
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
			if (timer_create(CLOCK_MONOTONIC, &sev, &t) != 0) {
				perror("timer_create");
				return 1;
			}
			head_kernel = kernel_cpu_ns();
			armed_at = clock_ns(CLOCK_MONOTONIC);
			if (timer_settime(t, 0, &its, NULL) != 0) {
				perror("timer_settime");
				return 1;
			}
			head_kernel = kernel_cpu_ns() - head_kernel;
			timer_gettime(t, &cur);
			left = cur.it_value.tv_sec * 1000000000LL + cur.it_value.tv_nsec;
			posix = t;
		}
		last_wait = kernel_cpu_ns();
		while (ticks < n) {
			compute_ns(CLOCK_PROCESS_CPUTIME_ID, work_ns);
			/* Expiries while the loop is out of sigsuspend stay
			 * pending and coalesce into one signal. Virtual time out
			 * of it is CPU tcs charged, no more than the kernel's
			 * from one sigsuspend to the next (the wait's own
			 * included): a round longer than a period by that clock
			 * (a pause of the machine, charged as CPU) may lose at
			 * most ceil(round / period) - 1 ticks. */
			long long now = kernel_cpu_ns(), round = now - last_wait;
			if (round > period)
				pause_ticks += (round + period - 1) / period - 1;
			last_wait = now;
			sigsuspend(&empty);
		}
		ticked = clock_ns(CLOCK_MONOTONIC) - armed_at;
		tail_kernel = kernel_cpu_ns() - last_wait;
		struct itimerval off = { { 0, 0 }, { 0, 0 } };
		setitimer(ITIMER_REAL, &off, NULL);
		if (posix)
			timer_delete(posix);
		sigprocmask(SIG_UNBLOCK, &block, NULL);
	}
	long long took_inner_cpu = clock_ns(CLOCK_PROCESS_CPUTIME_ID) - inner_start;
	long long took = clock_ns(CLOCK_MONOTONIC) - start;
	long long took_cpu = clock_ns(CLOCK_PROCESS_CPUTIME_ID) - cpu_start;
	long long took_kernel_cpu = kernel_cpu_ns() - kernel_start;
	long switches = kernel_voluntary_switches() - switches_start;
	long handled = ticks;
	/* alarm(1) interrupts sleep(5): it returns the 4 s it did not sleep. */
	signal(SIGALRM, on_tick);
	long long s0 = clock_ns(CLOCK_MONOTONIC);
	alarm(1);
	unsigned unslept = sleep(5);
	long long slept = clock_ns(CLOCK_MONOTONIC) - s0;
	printf("ticks=%ld\nloop_ns=%lld\nloop_cpu_ns=%lld\nloop_inner_cpu_ns=%lld\nloop_kernel_cpu_ns=%lld\nleft_ns=%lld\n"
	       "unslept=%u\nslept_ns=%lld\npause_ticks=%lld\nticked_ns=%lld\nhead_kernel_ns=%lld\ntail_kernel_ns=%lld\n"
	       "loop_switches=%ld\n",
	       handled, took, took_cpu, took_inner_cpu, took_kernel_cpu, left, unslept, slept, pause_ticks, ticked,
	       head_kernel, tail_kernel, switches);
	return 0;
}
