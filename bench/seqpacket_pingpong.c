/* seqpacket_pingpong [N]: the floor for a sleep round trip: two processes
 * on one core exchanging 48-byte messages over a SOCK_SEQPACKET socketpair
 * (what the preload and the coordinator do), wall ns per round trip. */
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <sys/wait.h>

#include "bench_time.h"

int main(int argc, char **argv)
{
	long n = argc > 1 ? atol(argv[1]) : 100000;
	int sv[2];
	char msg[48] = { 0 };
	bench_pin_to_last_cpu();
	if (socketpair(AF_UNIX, SOCK_SEQPACKET, 0, sv) != 0)
		return 1;
	pid_t pid = fork();
	if (pid == 0) {
		for (long i = 0; i < n; i++) {
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
	waitpid(pid, NULL, 0);
	printf("seqpacket_roundtrip_ns=%.0f\n", (t1 - t0) / n);
	return 0;
}
