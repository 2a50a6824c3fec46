/* spawn_start HOW: when a child started by HOW (vfork+exec, posix_spawn)
 * begins, on the clock it shares with its parent. The parent notes the
 * time, starts this program again as the child ("child"), and at once
 * polls every 100 us for 20 ms before it waits: virtual time must not pass
 * while the child's new program loads, so the child's first look at the
 * clock is the parent's time at the start (lockstep: exactly). Prints
 * started_ns= (parent) and child_start_ns= (child), CLOCK_MONOTONIC; with
 * the CPU-time clocks (under tcs the CPU charged: cpu mode adds it):
 * spawn_cpu_ns, the parent's from just before started_ns to just after
 * the call returned, and child_cpu_ns, the child's own (from when it began
 * to count as a controller of its own) just after its first look. */
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "work.h"

extern char **environ;

int main(int argc, char **argv)
{
	if (argc == 2 && strcmp(argv[1], "child") == 0) {
		long long at = clock_ns(CLOCK_MONOTONIC);
		printf("child_start_ns=%lld\nchild_cpu_ns=%lld\n", at, clock_ns(CLOCK_PROCESS_CPUTIME_ID));
		return 0;
	}
	if (argc != 2 || (strcmp(argv[1], "vfork") != 0 && strcmp(argv[1], "spawn") != 0)) {
		fprintf(stderr, "usage: spawn_start vfork|spawn\n");
		return 2;
	}
	fflush(stdout);
	char *child_argv[] = { argv[0], (char *)"child", NULL };
	long long cpu0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	long long started = clock_ns(CLOCK_MONOTONIC);
	pid_t pid;
	if (strcmp(argv[1], "vfork") == 0) {
		pid = vfork();
		if (pid == 0) {
			execv("/proc/self/exe", child_argv);
			_exit(127);
		}
	} else if (posix_spawn(&pid, "/proc/self/exe", NULL, NULL, child_argv, environ) != 0) {
		pid = -1;
	}
	long long spawn_cpu = clock_ns(CLOCK_PROCESS_CPUTIME_ID) - cpu0;
	if (pid < 0) {
		perror("spawn_start");
		return 1;
	}
	struct timespec poll_period = { 0, 100000 };
	for (int i = 0; i < 200; i++)
		nanosleep(&poll_period, NULL);
	int status;
	if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
		return 1;
	printf("started_ns=%lld\nspawn_cpu_ns=%lld\n", started, spawn_cpu);
	return 0;
}
