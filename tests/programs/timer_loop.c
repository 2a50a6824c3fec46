/* timer_loop HOW N PERIOD_US [WORK_US]: a loop paced by a periodic timerfd,
 * waiting on it with HOW: read (a blocking read), poll, select or epoll (then
 * reading it), N times, doing WORK_US of its own CPU time after each (more
 * than the period: the reads count the expirations it overran). Prints, as key=value lines, the expirations counted, the
 * monotonic time the loop took, what timerfd_gettime said right after
 * arming, and what a non-blocking read of a timer not yet due returned. */
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
	long long start = clock_ns(CLOCK_MONOTONIC);
	if (fd < 0 || timerfd_settime(fd, 0, &its, NULL) != 0) {
		perror("timerfd");
		return 1;
	}
	struct itimerspec left;
	timerfd_gettime(fd, &left);
	int ep = epoll_create1(EPOLL_CLOEXEC);
	struct epoll_event ev = { .events = EPOLLIN, .data.u64 = 42 };
	epoll_ctl(ep, EPOLL_CTL_ADD, fd, &ev);
	unsigned long long expirations = 0;
	long bad = 0;
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
		if (read(fd, &count, sizeof count) != sizeof count)
			bad++;
		else
			expirations += count;
		compute_ns(CLOCK_PROCESS_CPUTIME_ID, work_ns);
	}
	long long took = clock_ns(CLOCK_MONOTONIC) - start;
	/* A one-shot timer 1 s away: a non-blocking read is EAGAIN. */
	int once = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK);
	struct itimerspec later = { { 0, 0 }, { 1, 0 } };
	timerfd_settime(once, 0, &later, NULL);
	uint64_t c;
	int eagain = read(once, &c, sizeof c) < 0 && errno == EAGAIN;
	printf("expirations=%llu\nloop_ns=%lld\nfirst_left_ns=%lld\ninterval_ns=%lld\nbad=%ld\neagain=%d\n", expirations,
	       took, left.it_value.tv_sec * 1000000000LL + left.it_value.tv_nsec,
	       left.it_interval.tv_sec * 1000000000LL + left.it_interval.tv_nsec, bad, eagain);
	return 0;
}
