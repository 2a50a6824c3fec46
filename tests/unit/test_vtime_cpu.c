/* Unit tests for tcs/vtime.h, shared by the preload and the coordinator:
 * the one CPU -> virtual time formula (tcs_scale_cpu), a slice's CPU
 * (tcs_slice_cpu) and the runtime's own reads left out (tcs_less_own). */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <tcs/vtime.h>

#include "test_i64.h"

/* ---- tcs_scale_cpu --------------------------------------------------------- */

static void test_scale_cpu_identity_exact(void **state)
{
	assert_i64_eq(tcs_scale_cpu(0, 1.0), 0);
	assert_i64_eq(tcs_scale_cpu(1, 1.0), 1);
	assert_i64_eq(tcs_scale_cpu(999999999, 1.0), 999999999);
	assert_i64_eq(tcs_scale_cpu(1000000000000000LL, 1.0), 1000000000000000LL);
	assert_i64_eq(tcs_scale_cpu(1000000000000001LL, 1.0), 1000000000000001LL);
	assert_i64_eq(tcs_scale_cpu(123456789012345LL, 1.0), 123456789012345LL);
	assert_i64_eq(tcs_scale_cpu((1LL << 53) - 1, 1.0), (1LL << 53) - 1);
	/* A day of CPU, nanosecond by nanosecond near it. */
	for (int64_t ns = 86400LL * TCS_NS_PER_S - 1000; ns <= 86400LL * TCS_NS_PER_S + 1000; ns++)
		assert_i64_eq(tcs_scale_cpu(ns, 1.0), ns);
}

static void test_scale_cpu_factors(void **state)
{
	assert_i64_eq(tcs_scale_cpu(1000000000000000LL, 3.0), 3000000000000000LL);
	assert_i64_eq(tcs_scale_cpu(1000000000000000LL, 0.5), 500000000000000LL);
	assert_i64_eq(tcs_scale_cpu(1000000000000000LL, 2.0), 2000000000000000LL);
	assert_i64_eq(tcs_scale_cpu(7, 3.0), 21);
	assert_i64_eq(tcs_scale_cpu(250000000, 0.5), 125000000);
	assert_i64_eq(tcs_scale_cpu(1000, 0.25), 250);
}

static void test_scale_cpu_rounds_down(void **state)
{
	assert_i64_eq(tcs_scale_cpu(1, 0.5), 0);
	assert_i64_eq(tcs_scale_cpu(3, 0.5), 1);
	assert_i64_eq(tcs_scale_cpu(1000000007, 0.5), 500000003);
	assert_i64_eq(tcs_scale_cpu(1, 0.25), 0);
	assert_i64_eq(tcs_scale_cpu(7, 0.25), 1);
	assert_i64_eq(tcs_scale_cpu(10, 1.0 / 3.0), 3);
	assert_i64_eq(tcs_scale_cpu(1, 0.999), 0);
	/* Rounded down: never more than the exact product. */
	uint64_t rng = 4242;
	for (int i = 0; i < 100000; i++) {
		int64_t cpu = (int64_t)(test_rand(&rng) % 100000000000ULL);
		/* Binary fractions: the double product is exact, so rounding is the only error. */
		double scale = (double)(test_rand(&rng) % 10000 + 1) / 1024.0;
		int64_t got = tcs_scale_cpu(cpu, scale);
		long double exact = (long double)cpu * (long double)scale;
		assert_true((long double)got <= exact);
		assert_true((long double)got > exact - 1.0L);
	}
}

static void test_scale_cpu_never_negative(void **state)
{
	assert_i64_eq(tcs_scale_cpu(-1, 1.0), 0);
	assert_i64_eq(tcs_scale_cpu(-1000000000000000LL, 3.0), 0);
	assert_i64_eq(tcs_scale_cpu(INT64_MIN, 1.0), 0);
	assert_i64_eq(tcs_scale_cpu(5, -1.0), 0);
	assert_i64_eq(tcs_scale_cpu(INT64_MAX, -1.0), 0);
	assert_i64_eq(tcs_scale_cpu(5, 0.0), 0);
	assert_i64_eq(tcs_scale_cpu(5, NAN), 0);
	assert_i64_eq(tcs_scale_cpu(-5, INFINITY), 0);
	uint64_t rng = 31337;
	for (int i = 0; i < 100000; i++) {
		int64_t cpu = (int64_t)test_rand(&rng);
		double scale = ((double)(int64_t)test_rand(&rng)) / 1e15;
		assert_i64_ge(tcs_scale_cpu(cpu, scale), 0);
	}
}

static void test_scale_cpu_saturates(void **state)
{
	assert_i64_eq(tcs_scale_cpu(INT64_MAX, 1.0), TCS_NEVER);
	assert_i64_eq(tcs_scale_cpu(INT64_MAX, 3.0), TCS_NEVER);
	assert_i64_eq(tcs_scale_cpu(4000000000000000000LL, 3.0), TCS_NEVER);
	assert_i64_eq(tcs_scale_cpu(1000000000000000000LL, 1e6), TCS_NEVER);
	assert_i64_eq(tcs_scale_cpu(1, INFINITY), TCS_NEVER);
	assert_i64_eq(tcs_scale_cpu(1, 1e300), TCS_NEVER);
	/* Large but representable products are not saturated. */
	assert_i64_eq(tcs_scale_cpu(3000000000000000000LL, 3.0), 9000000000000000000LL);
	assert_i64_eq(tcs_scale_cpu(1LL << 62, 0.5), 1LL << 61);
}

/* Larger CPU never gives less virtual time, at any scale. */
static void test_scale_cpu_monotonic(void **state)
{
	static const double scales[] = { 1.0, 3.0, 0.5, 0.37, 1.0 / 3.0, 1e-6, 1000.0, 1e6 };
	uint64_t rng = 2024;
	for (size_t s = 0; s < sizeof scales / sizeof scales[0]; s++) {
		int64_t cpu = 0, last = 0;
		for (int i = 0; i < 20000; i++) {
			int64_t step = (int64_t)(test_rand(&rng) >> (1 + (test_rand(&rng) % 63)));
			cpu = tcs_ns_add(cpu, step);
			int64_t got = tcs_scale_cpu(cpu, scales[s]);
			assert_i64_ge(got, last);
			last = got;
		}
	}
}

/* ---- tcs_slice_cpu --------------------------------------------------------- */

static void test_slice_cpu_mark_before_base(void **state)
{
	/* The controller's mark is from an earlier slice: count from the base. */
	assert_i64_eq(tcs_slice_cpu(100, 0, 150), 50);
	assert_i64_eq(tcs_slice_cpu(100, 99, 150), 50);
	assert_i64_eq(tcs_slice_cpu(100, 100, 150), 50);
	assert_i64_eq(tcs_slice_cpu(100, -5, 150), 50);
	assert_i64_eq(tcs_slice_cpu(100, INT64_MIN, 150), 50);
	assert_i64_eq(tcs_slice_cpu(0, INT64_MIN, INT64_MAX), INT64_MAX);
}

static void test_slice_cpu_mark_after_base(void **state)
{
	/* The hook's own cost (base..mark) is not charged. */
	assert_i64_eq(tcs_slice_cpu(100, 120, 150), 30);
	assert_i64_eq(tcs_slice_cpu(100, 149, 150), 1);
	assert_i64_eq(tcs_slice_cpu(100, 150, 150), 0);
	assert_i64_eq(tcs_slice_cpu(1000000000, 1000005000, 3000000000LL), 1999995000);
}

static void test_slice_cpu_lying_mark(void **state)
{
	/* A mark beyond now (a lying or corrupted controller) charges nothing. */
	assert_i64_eq(tcs_slice_cpu(100, 151, 150), 0);
	assert_i64_eq(tcs_slice_cpu(100, 1000000, 150), 0);
	assert_i64_eq(tcs_slice_cpu(100, INT64_MAX, 150), 0);
	assert_i64_eq(tcs_slice_cpu(INT64_MIN, INT64_MAX, 0), 0);
}

static void test_slice_cpu_never_negative(void **state)
{
	/* now before the base (the CPU clock cannot go back, but be safe). */
	assert_i64_eq(tcs_slice_cpu(100, 0, 50), 0);
	assert_i64_eq(tcs_slice_cpu(100, 0, 100), 0);
	assert_i64_eq(tcs_slice_cpu(INT64_MAX, INT64_MAX, 0), 0);
	uint64_t rng = 5150;
	for (int i = 0; i < 200000; i++) {
		int64_t base = (int64_t)(test_rand(&rng) >> 2);
		int64_t mark = (int64_t)test_rand(&rng);
		int64_t now = (int64_t)(test_rand(&rng) >> 2);
		if (i & 1) { /* close together, so that all orderings occur */
			mark = base + (int64_t)(test_rand(&rng) % 2001) - 1000;
			now = base + (int64_t)(test_rand(&rng) % 2001) - 1000;
		}
		int64_t got = tcs_slice_cpu(base, mark, now);
		int64_t from = mark > base ? mark : base;
		assert_i64_ge(got, 0);
		assert_i64_eq(got, now > from ? now - from : 0);
		assert_true(got <= (now > base ? now - base : 0));
	}
}

/* ---- tcs_less_own ---------------------------------------------------------- */

static void test_less_own_excludes_the_runtimes_reads(void **state)
{
	assert_i64_eq(tcs_less_own(500, 1000, 1000), 500); /* none in the slice */
	assert_i64_eq(tcs_less_own(500, 1000, 1120), 380);
	assert_i64_eq(tcs_less_own(500, 0, 500), 0);
	assert_i64_eq(tcs_less_own(0, 0, 7), 0);
}

static void test_less_own_lying_controller(void **state)
{
	/* A credit beyond the slice, gone back, or wrapped charges within 0..used. */
	assert_i64_eq(tcs_less_own(500, 0, 501), 0);
	assert_i64_eq(tcs_less_own(500, 0, INT64_MAX), 0);
	assert_i64_eq(tcs_less_own(500, 1000, 10), 500);
	assert_i64_eq(tcs_less_own(500, INT64_MIN, INT64_MAX), 0);
	assert_i64_eq(tcs_less_own(500, INT64_MAX, INT64_MIN), 500);
	uint64_t rng = 77;
	for (int i = 0; i < 200000; i++) {
		int64_t used = (int64_t)(test_rand(&rng) >> 2);
		int64_t base = (int64_t)test_rand(&rng), now = (int64_t)test_rand(&rng);
		if (i & 1)
			now = base + (int64_t)(test_rand(&rng) % 2001) - 1000;
		int64_t got = tcs_less_own(used, base, now);
		assert_true(got >= 0 && got <= used);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_scale_cpu_identity_exact),
		cmocka_unit_test(test_scale_cpu_factors),
		cmocka_unit_test(test_scale_cpu_rounds_down),
		cmocka_unit_test(test_scale_cpu_never_negative),
		cmocka_unit_test(test_scale_cpu_saturates),
		cmocka_unit_test(test_scale_cpu_monotonic),
		cmocka_unit_test(test_slice_cpu_mark_before_base),
		cmocka_unit_test(test_slice_cpu_mark_after_base),
		cmocka_unit_test(test_slice_cpu_lying_mark),
		cmocka_unit_test(test_slice_cpu_never_negative),
		cmocka_unit_test(test_less_own_excludes_the_runtimes_reads),
		cmocka_unit_test(test_less_own_lying_controller),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
