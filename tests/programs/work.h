/* What test controllers share: a fixed amount of computation (n rounds of
 * integer arithmetic the compiler cannot remove, whose CPU cost `calibrate`
 * measures natively, so a test knows what the work should cost) and a clock
 * read in nanoseconds. */
#ifndef TCS_TEST_WORK_H
#define TCS_TEST_WORK_H

#include <stdint.h>
#include <time.h>

static inline long long clock_ns(clockid_t clock)
{
	struct timespec ts;
	clock_gettime(clock, &ts);
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static inline uint64_t work(uint64_t n)
{
	static volatile uint64_t sink;
	uint64_t x = sink + 88172645463325252ull;
	for (uint64_t i = 0; i < n; i++) {
		x ^= x << 13;
		x ^= x >> 7;
		x ^= x << 17;
	}
	sink = x;
	return x;
}

#endif
