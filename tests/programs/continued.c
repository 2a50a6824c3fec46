/* continued ROUNDS: does ROUNDS of work() and prints, as key=value lines,
 * how long that took by its monotonic clock (span_ns: its virtual time
 * under tcs), what the kernel charged it meanwhile (kernel_cpu_ns, read
 * around the span) and how many times it was continued after a stop
 * meanwhile (continues: a SIGCONT handler counts them; nothing else in a
 * process can see that it was stopped). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "work.h"

static volatile sig_atomic_t continues;

static void on_continue(int sig)
{
	(void)sig;
	continues++;
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: continued ROUNDS\n");
		return 2;
	}
	unsigned long long rounds = strtoull(argv[1], NULL, 10);
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_continue;
	sa.sa_flags = SA_RESTART;
	sigaction(SIGCONT, &sa, NULL);
	clock_ns(CLOCK_MONOTONIC); /* bound before the span (the linker's work) */
	long long k0 = kernel_cpu_ns();
	long long m0 = clock_ns(CLOCK_MONOTONIC);
	int c0 = continues;
	work(rounds);
	int c1 = continues;
	long long m1 = clock_ns(CLOCK_MONOTONIC);
	long long k1 = kernel_cpu_ns();
	printf("span_ns=%lld\nkernel_cpu_ns=%lld\ncontinues=%d\n", m1 - m0, k1 - k0, c1 - c0);
	return 0;
}
