/* children HOW: starts a child that sleeps 1 s (HOW: fork, vfork, spawn
 * for posix_spawn of /bin/sleep, system for system("sleep 1")), then the
 * parent sleeps 0.5 s and waits for it; a forked child also burns 200 ms
 * of its own CPU first. Prints, as key=value lines, how much time the
 * parent's monotonic clock saw pass, how much CPU the kernel charged it
 * (parent_cpu_ns) and its waited-for children (children_cpu_ns) meanwhile,
 * read with system calls of our own (work.h: not the clocks tcs answers),
 * and the child's exit status. */
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
	if (argc != 2) {
		fprintf(stderr, "usage: children fork|vfork|spawn|system\n");
		return 2;
	}
	const char *how = argv[1];
	long long cpu0 = kernel_cpu_ns();
	long long t0 = clock_ns(CLOCK_MONOTONIC);
	int status = -1;
	pid_t pid = -1;
	if (strcmp(how, "system") == 0) {
		status = system("sleep 1");
	} else {
		if (strcmp(how, "fork") == 0) {
			pid = fork();
			if (pid == 0) {
				compute_ns(CLOCK_PROCESS_CPUTIME_ID, 200000000LL);
				sleep(1);
				_exit(7);
			}
		} else if (strcmp(how, "vfork") == 0) {
			pid = vfork();
			if (pid == 0) {
				execl("/bin/sleep", "sleep", "1", (char *)NULL);
				_exit(127);
			}
		} else {
			char *args[] = { "sleep", "1", NULL };
			if (posix_spawn(&pid, "/bin/sleep", NULL, NULL, args, environ) != 0)
				pid = -1;
		}
		if (pid < 0) {
			perror("start");
			return 1;
		}
		usleep(500000);
		if (waitpid(pid, &status, 0) != pid)
			perror("waitpid");
	}
	long long took = clock_ns(CLOCK_MONOTONIC) - t0;
	long long cpu = kernel_cpu_ns() - cpu0, children = kernel_children_cpu_ns();
	printf("parent_ns=%lld\nparent_cpu_ns=%lld\nchildren_cpu_ns=%lld\nchild_status=%d\n", took, cpu, children,
	       WIFEXITED(status) ? WEXITSTATUS(status) : -1);
	return 0;
}
