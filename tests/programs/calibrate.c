/* Prints how many rounds of work() cost one millisecond of CPU on this
 * machine, natively: the median of several measurements. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "work.h"

static double cpu_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return ts.tv_sec + ts.tv_nsec / 1e9;
}

static int cmp(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

int main(void)
{
	const uint64_t n = 2000000;
	double per_ms[7];
	work(n); /* warm up */
	for (int i = 0; i < 7; i++) {
		double t0 = cpu_s();
		work(n);
		per_ms[i] = n / ((cpu_s() - t0) * 1e3);
	}
	qsort(per_ms, 7, sizeof per_ms[0], cmp);
	printf("%.0f\n", per_ms[3]);
	return 0;
}
