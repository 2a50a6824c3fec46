/* after_end PERIOD_US AFTER: sleeps PERIOD_US at a time until SIGTERM (the
 * run's end), then sleeps 1 ms and reads its clock AFTER times more and
 * exits 0: what a program does after the run's end began, for --replay
 * (docs/DESIGN.md §2: that is no departure from the record). Prints
 * loops=N and after=AFTER. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static volatile sig_atomic_t ended;

static void on_term(int sig)
{
	(void)sig;
	ended = 1;
}

int main(int argc, char **argv)
{
	if (argc != 3)
		return 2;
	long period = atol(argv[1]) * 1000, after = atol(argv[2]), loops = 0;
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_term;
	sigaction(SIGTERM, &sa, NULL);
	while (!ended) {
		struct timespec d = { period / 1000000000L, period % 1000000000L };
		nanosleep(&d, NULL);
		loops++;
	}
	for (long i = 0; i < after; i++) {
		struct timespec d = { 0, 1000000 }, t;
		nanosleep(&d, NULL);
		clock_gettime(CLOCK_MONOTONIC, &t);
	}
	printf("loops=%ld\nafter=%ld\n", loops, after);
	return 0;
}
