/* multiplex: timeouts of select/pselect/poll/ppoll/epoll_wait/epoll_pwait
 * on real fds with nothing to read last exactly their virtual timeout; a
 * real fd that is ready is reported at once; select reports time left. */
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <sys/epoll.h>
#include <sys/select.h>
#include <time.h>
#include <unistd.h>

#include "work.h"

int main(void)
{
	int p[2];
	if (pipe(p) != 0)
		return 1;
	long long t;
	struct pollfd pfd = { p[0], POLLIN, 0 };

	t = clock_ns(CLOCK_MONOTONIC);
	int r = poll(&pfd, 1, 200);
	printf("poll=%d elapsed_ns=%lld\n", r, clock_ns(CLOCK_MONOTONIC) - t);

	struct timespec ts = { 0, 300000000 };
	sigset_t mask;
	sigemptyset(&mask);
	t = clock_ns(CLOCK_MONOTONIC);
	r = ppoll(&pfd, 1, &ts, &mask);
	printf("ppoll=%d elapsed_ns=%lld\n", r, clock_ns(CLOCK_MONOTONIC) - t);

	fd_set rs;
	FD_ZERO(&rs);
	FD_SET(p[0], &rs);
	struct timeval tv = { 0, 400000 };
	t = clock_ns(CLOCK_MONOTONIC);
	r = select(p[0] + 1, &rs, NULL, NULL, &tv);
	printf("select=%d elapsed_ns=%lld isset=%d tv_left_us=%ld\n", r, clock_ns(CLOCK_MONOTONIC) - t, FD_ISSET(p[0], &rs),
	       (long)(tv.tv_sec * 1000000 + tv.tv_usec));

	FD_SET(p[0], &rs);
	ts.tv_nsec = 500000000;
	t = clock_ns(CLOCK_MONOTONIC);
	r = pselect(p[0] + 1, &rs, NULL, NULL, &ts, &mask);
	printf("pselect=%d elapsed_ns=%lld\n", r, clock_ns(CLOCK_MONOTONIC) - t);

	int ep = epoll_create1(0);
	struct epoll_event ev = { .events = EPOLLIN, .data.fd = p[0] }, out;
	epoll_ctl(ep, EPOLL_CTL_ADD, p[0], &ev);
	t = clock_ns(CLOCK_MONOTONIC);
	r = epoll_wait(ep, &out, 1, 600);
	printf("epoll_wait=%d elapsed_ns=%lld\n", r, clock_ns(CLOCK_MONOTONIC) - t);
	t = clock_ns(CLOCK_MONOTONIC);
	r = epoll_pwait(ep, &out, 1, 700, &mask);
	printf("epoll_pwait=%d elapsed_ns=%lld\n", r, clock_ns(CLOCK_MONOTONIC) - t);

	/* Ready before the call: reported at once, no time passes. */
	(void)!write(p[1], "x", 1);
	t = clock_ns(CLOCK_MONOTONIC);
	r = poll(&pfd, 1, 5000);
	printf("ready_poll=%d revents_in=%d elapsed_ns=%lld\n", r, !!(pfd.revents & POLLIN), clock_ns(CLOCK_MONOTONIC) - t);
	FD_ZERO(&rs);
	FD_SET(p[0], &rs);
	tv.tv_sec = 5;
	tv.tv_usec = 0;
	r = select(p[0] + 1, &rs, NULL, NULL, &tv);
	printf("ready_select=%d isset=%d\n", r, FD_ISSET(p[0], &rs));
	r = epoll_wait(ep, &out, 1, 5000);
	printf("ready_epoll=%d fd_ok=%d\n", r, out.data.fd == p[0]);
	return 0;
}
