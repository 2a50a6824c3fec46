/* clock_reads N: reads CLOCK_MONOTONIC N times without a wait between,
 * then sleeps 1 ms: a program whose clock reads, each an entry of a
 * recording's journal (docs/DESIGN.md §2, Record and replay), can outrun
 * what the journal holds between two stops. Prints reads=N and whether
 * the clock ever went back (backwards). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

int main(int argc, char **argv)
{
	long n = argc == 2 ? atol(argv[1]) : 0;
	struct timespec last = { 0, 0 }, t;
	long backwards = 0;
	for (long i = 0; i < n; i++) {
		clock_gettime(CLOCK_MONOTONIC, &t);
		if (t.tv_sec < last.tv_sec || (t.tv_sec == last.tv_sec && t.tv_nsec < last.tv_nsec))
			backwards++;
		last = t;
	}
	struct timespec d = { 0, 1000000 };
	nanosleep(&d, NULL);
	printf("reads=%ld\nbackwards=%ld\n", n, backwards);
	return 0;
}
