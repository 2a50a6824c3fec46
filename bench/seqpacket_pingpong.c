/* seqpacket_pingpong [N] [--event-loop]: the floor for a sleep round trip:
 * two processes on one core exchanging 48-byte messages over a
 * SOCK_SEQPACKET socketpair (what the preload and the coordinator do), wall
 * ns per round trip.
 *
 * --event-loop adds the system call a sleep's round trip under tcs cannot
 * do without: the answering side waits in epoll_wait (a coordinator serves
 * many fds, not one). (In lockstep the asking side reads no CPU-time clock:
 * libtcs_preload/cpu_estimate.c.) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>

#include "bench_time.h"

int main(int argc, char **argv)
{
	long n = argc > 1 ? atol(argv[1]) : 100000;
	int event_loop = argc > 2 && strcmp(argv[2], "--event-loop") == 0;
	int sv[2];
	char msg[48] = { 0 };
	bench_pin_to_last_cpu();
	if (socketpair(AF_UNIX, SOCK_SEQPACKET, 0, sv) != 0)
		return 1;
	pid_t pid = fork();
	if (pid == 0) {
		int ep = epoll_create1(0);
		struct epoll_event ev = { .events = EPOLLIN };
		if (ep < 0 || epoll_ctl(ep, EPOLL_CTL_ADD, sv[1], &ev) != 0)
			_exit(1);
		for (long i = 0; i < n; i++) {
			if (event_loop && epoll_wait(ep, &ev, 1, -1) != 1)
				_exit(1);
			if (recv(sv[1], msg, sizeof msg, 0) != sizeof msg || send(sv[1], msg, sizeof msg, 0) != sizeof msg)
				_exit(1);
		}
		_exit(0);
	}
	double t0 = bench_wall_ns();
	for (long i = 0; i < n; i++) {
		send(sv[0], msg, sizeof msg, 0);
		recv(sv[0], msg, sizeof msg, 0);
	}
	double t1 = bench_wall_ns();
	int status;
	waitpid(pid, &status, 0);
	if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
		return 1;
	printf("seqpacket_roundtrip_ns=%.0f\n", (t1 - t0) / n);
	return 0;
}
