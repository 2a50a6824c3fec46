/* A fixed amount of computation for test controllers: n rounds of integer
 * arithmetic the compiler cannot remove. Its cost in CPU time is measured
 * natively by `calibrate`, so a test knows what the work should cost. */
#ifndef TCS_TEST_WORK_H
#define TCS_TEST_WORK_H

#include <stdint.h>

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
