/* raw_block MS: reads CLOCK_MONOTONIC, then sleeps MS milliseconds in a raw
 * nanosleep system call (which no hook sees: to tcs it is neither a wait nor
 * computation), then a tight loop of clock reads for as long again, and
 * prints, as key=value lines, how much its monotonic clock advanced over the
 * raw sleep and whether any read in the loop went backwards. Under cpu mode
 * the sleep costs no CPU and so no virtual time: a clock estimated from the
 * TSC (TCS_PAGE_CPU_ESTIMATE) may err by its resync interval, no more. */
#include <stdio.h>
#include <stdlib.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "work.h"

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: raw_block MS\n");
		return 2;
	}
	long ms = atol(argv[1]);
	long long before = clock_ns(CLOCK_MONOTONIC);
	struct timespec ts = { ms / 1000, ms % 1000 * 1000000L };
	syscall(SYS_nanosleep, &ts, NULL);
	long long after = clock_ns(CLOCK_MONOTONIC);
	long long last = after, backwards = 0, reads = 0;
	long long cpu0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	while (clock_ns(CLOCK_PROCESS_CPUTIME_ID) - cpu0 < ms * 1000000LL) {
		for (int i = 0; i < 1000; i++) {
			long long now = clock_ns(CLOCK_MONOTONIC);
			backwards += now < last;
			last = now;
			reads++;
		}
	}
	printf("raw_sleep_virtual_ns=%lld\nreads=%lld\nbackwards=%lld\n", after - before, reads, backwards);
	return 0;
}
