/* kernel_cpu_of COMMAND [ARGS...]: runs COMMAND as a child, waits for it,
 * and prints how long it took on this process's monotonic clock (took_ns:
 * under tcs, virtual time) and the CPU the kernel charged the whole tree
 * meanwhile: tree_kernel_cpu_ns, the children's (waited for, all their
 * descendants that were waited for included) and this process's own, both
 * read with system calls of our own (work.h), not the clocks tcs answers.
 * A test bounds the virtual time a program took by what the kernel says it
 * computed, not by what tcs's summary says. Exits with COMMAND's status
 * (128 + the signal that ended it). */
#include <spawn.h>
#include <stdio.h>
#include <sys/wait.h>

#include "work.h"

extern char **environ;

int main(int argc, char **argv)
{
	if (argc < 2) {
		fprintf(stderr, "usage: kernel_cpu_of COMMAND [ARGS...]\n");
		return 2;
	}
	long long own0 = kernel_cpu_ns(), t0 = clock_ns(CLOCK_MONOTONIC);
	pid_t pid;
	if (posix_spawnp(&pid, argv[1], NULL, NULL, argv + 1, environ) != 0) {
		perror(argv[1]);
		return 127;
	}
	int status = 0;
	while (waitpid(pid, &status, 0) < 0)
		;
	long long took = clock_ns(CLOCK_MONOTONIC) - t0;
	long long tree = kernel_children_cpu_ns() + kernel_cpu_ns() - own0;
	printf("took_ns=%lld\ntree_kernel_cpu_ns=%lld\n", took, tree);
	return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}
