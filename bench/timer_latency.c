/* timer_latency [N]: the floor for preemption overshoot. A SCHED_FIFO
 * process arms a 1 ms timerfd N times while a lower-priority SCHED_FIFO
 * process spins on the same core (as the coordinator and a computing
 * controller do), and measures how late it runs after each expiry: the
 * time the spinning process keeps the core past its budget before anyone
 * can stop it. Prints p50 and p99 in ns. Needs SCHED_FIFO (root or
 * CAP_SYS_NICE); without it, says so and measures at normal priority. */
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/timerfd.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_time.h"

static int cmp(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
	long n = argc > 1 ? atol(argv[1]) : 2000;
	bench_pin_to_last_cpu();
	struct sched_param sp = { .sched_priority = 3 };
	int fifo = sched_setscheduler(0, SCHED_FIFO, &sp) == 0;
	if (!fifo)
		fprintf(stderr, "timer_latency: SCHED_FIFO not permitted: measuring at normal priority\n");
	pid_t spinner = fork();
	if (spinner == 0) {
		struct sched_param low = { .sched_priority = 2 };
		if (fifo)
			sched_setscheduler(0, SCHED_FIFO, &low);
		for (volatile unsigned long x = 0;; x++) {
		}
	}
	int tfd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
	double *late = malloc(sizeof *late * (size_t)n);
	for (long i = 0; i < n; i++) {
		struct itimerspec its = { .it_value = { 0, 1000000 } };
		double armed = bench_wall_ns();
		timerfd_settime(tfd, 0, &its, NULL);
		unsigned long long ticks;
		if (read(tfd, &ticks, sizeof ticks) != (ssize_t)sizeof ticks)
			break;
		late[i] = bench_wall_ns() - armed - 1e6;
	}
	kill(spinner, SIGKILL);
	waitpid(spinner, NULL, 0);
	qsort(late, (size_t)n, sizeof *late, cmp);
	printf("timer_late_p50_ns=%.0f\ntimer_late_p99_ns=%.0f\nfifo=%d\n", late[n / 2], late[n * 99 / 100], fifo);
	return 0;
}
