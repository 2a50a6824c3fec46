/* timer_loop HOW N PERIOD_US [WORK_US]: a loop paced by a periodic timerfd,
 * waiting on it with HOW: read (a blocking read), poll, select or epoll (then
 * reading it), N times, doing WORK_US of its own CPU time (by the kernel's
 * clock: work.h) after each (more than the period: the reads count the
 * expirations it overran). Prints, as key=value lines, the expirations
 * counted, the monotonic time the loop took (from just before the arming),
 * what timerfd_gettime said right after arming, and what a non-blocking read
 * of a timer not yet due returned; and, monotonic from that start: armed_ns
 * (just after the arming call), first_ns (just after the first read),
 * last_read_from_ns and last_read_to_ns (around the last read); with the
 * process's CPU by the kernel's clock (work.h: not the CPU clock tcs
 * answers, so that a test bounds tcs's charges by the kernel's): first_cpu_ns
 * from just before the start to just after first_ns; from first_ns to the
 * end, busy_cpu_ns read just outside those two clock reads (all of the
 * span in it) and busy_inner_cpu_ns just inside them (none but the span). */
#include <errno.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/select.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include "work.h"

int main(int argc, char **argv)
{
	if (argc != 4 && argc != 5) {
		fprintf(stderr, "usage: timer_loop read|poll|select|epoll N PERIOD_US [WORK_US]\n");
		return 2;
	}
	const char *how = argv[1];
	long n = atol(argv[2]);
	long long period = atoll(argv[3]) * 1000LL;
	long long work_ns = argc == 5 ? atoll(argv[4]) * 1000LL : 0;
	int fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
	struct itimerspec its = { { period / 1000000000, period % 1000000000 }, { period / 1000000000, period % 1000000000 } };
	long long cpu0 = kernel_cpu_ns();
	long long start = clock_ns(CLOCK_MONOTONIC);
	if (fd < 0 || timerfd_settime(fd, 0, &its, NULL) != 0) {
		perror("timerfd");
		return 1;
	}
	long long armed = clock_ns(CLOCK_MONOTONIC) - start;
	struct itimerspec left;
	timerfd_gettime(fd, &left);
	int ep = epoll_create1(EPOLL_CLOEXEC);
	struct epoll_event ev = { .events = EPOLLIN, .data.u64 = 42 };
	epoll_ctl(ep, EPOLL_CTL_ADD, fd, &ev);
	unsigned long long expirations = 0;
	long bad = 0;
	long long first = -1, first_cpu = -1, busy_outer0 = 0, busy_inner0 = 0, read_from = -1, read_to = -1;
	for (long i = 0; i < n; i++) {
		if (strcmp(how, "poll") == 0) {
			struct pollfd p = { fd, POLLIN, 0 };
			bad += poll(&p, 1, -1) != 1 || !(p.revents & POLLIN);
		} else if (strcmp(how, "select") == 0) {
			fd_set r;
			FD_ZERO(&r);
			FD_SET(fd, &r);
			bad += select(fd + 1, &r, NULL, NULL, NULL) != 1 || !FD_ISSET(fd, &r);
		} else if (strcmp(how, "epoll") == 0) {
			struct epoll_event got;
			bad += epoll_wait(ep, &got, 1, -1) != 1 || got.data.u64 != 42;
		}
		uint64_t count;
		read_from = clock_ns(CLOCK_MONOTONIC) - start;
		if (read(fd, &count, sizeof count) != sizeof count)
			bad++;
		else
			expirations += count;
		if (i == 0)
			busy_outer0 = kernel_cpu_ns();
		read_to = clock_ns(CLOCK_MONOTONIC) - start;
		if (i == 0) {
			first = read_to;
			busy_inner0 = kernel_cpu_ns();
			first_cpu = busy_inner0 - cpu0;
		}
		compute_ns(CLOCK_PROCESS_CPUTIME_ID, work_ns);
	}
	long long busy_inner = kernel_cpu_ns() - busy_inner0;
	long long took = clock_ns(CLOCK_MONOTONIC) - start;
	long long busy_outer = kernel_cpu_ns() - busy_outer0;
	/* A one-shot timer 1 s away: a non-blocking read is EAGAIN. */
	int once = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK);
	struct itimerspec later = { { 0, 0 }, { 1, 0 } };
	timerfd_settime(once, 0, &later, NULL);
	uint64_t c;
	int eagain = read(once, &c, sizeof c) < 0 && errno == EAGAIN;
	printf("expirations=%llu\nloop_ns=%lld\nfirst_left_ns=%lld\ninterval_ns=%lld\nbad=%ld\neagain=%d\n", expirations,
	       took, left.it_value.tv_sec * 1000000000LL + left.it_value.tv_nsec,
	       left.it_interval.tv_sec * 1000000000LL + left.it_interval.tv_nsec, bad, eagain);
	printf("armed_ns=%lld\nfirst_ns=%lld\nfirst_cpu_ns=%lld\nbusy_cpu_ns=%lld\nbusy_inner_cpu_ns=%lld\nlast_read_from_ns=%lld\n"
	       "last_read_to_ns=%lld\n",
	       armed, first, first_cpu, busy_outer, busy_inner, read_from, read_to);
	return 0;
}
