/* Helpers shared by the C unit tests: signed 64-bit assertions with readable
 * failure messages (cmocka 1.1 prints everything as unsigned), and a small
 * deterministic PRNG for the randomised tests. Include after <cmocka.h>. */
#ifndef TCS_TEST_I64_H
#define TCS_TEST_I64_H

#include <stdint.h>

#define assert_i64_eq(a, b)                                                                                  \
	do {                                                                                                 \
		int64_t a_ = (int64_t)(a), b_ = (int64_t)(b);                                                \
		if (a_ != b_) {                                                                              \
			print_error("%s == %lld, expected %s == %lld\n", #a, (long long)a_, #b, (long long)b_); \
			fail();                                                                              \
		}                                                                                            \
	} while (0)

#define assert_i64_ge(a, b)                                                                                  \
	do {                                                                                                 \
		int64_t a_ = (int64_t)(a), b_ = (int64_t)(b);                                                \
		if (!(a_ >= b_)) {                                                                           \
			print_error("%s == %lld, expected >= %s == %lld\n", #a, (long long)a_, #b, (long long)b_); \
			fail();                                                                              \
		}                                                                                            \
	} while (0)

/* xorshift64*: fixed seed, same sequence on every run and machine. */
static inline uint64_t test_rand(uint64_t *state)
{
	uint64_t x = *state;
	x ^= x >> 12;
	x ^= x << 25;
	x ^= x >> 27;
	*state = x;
	return x * 0x2545F4914F6CDD1DULL;
}

#endif
