/* Unit tests for tcs/vtime.h: the time arithmetic shared by the preload and
 * the coordinator. */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <tcs/vtime.h>

#include "test_i64.h"

/* The largest tv_sec whose every nanosecond value fits in an int64_t. */
#define MAX_EXACT_SEC 9223372035LL

static struct timespec ts_make(time_t sec, long nsec)
{
	struct timespec ts;
	ts.tv_sec = sec;
	ts.tv_nsec = nsec;
	return ts;
}

/* ---- tcs_ts_valid ---------------------------------------------------------- */

static void test_ts_valid_accepts_valid(void **state)
{
	struct timespec ok[] = {
		ts_make(0, 0),
		ts_make(0, 1),
		ts_make(1, 999999999),
		ts_make(1714564800, 500000000),
		ts_make((time_t)INT64_MAX, 999999999),
	};
	for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++)
		assert_true(tcs_ts_valid(&ok[i]));
}

static void test_ts_valid_rejects_invalid(void **state)
{
	struct timespec bad[] = {
		ts_make(-1, 0),
		ts_make(-1, 999999999),
		ts_make((time_t)INT64_MIN, 0),
		ts_make(0, -1),
		ts_make(0, 1000000000),
		ts_make(5, LONG_MAX),
		ts_make(5, LONG_MIN),
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		assert_false(tcs_ts_valid(&bad[i]));
}

/* ---- tcs_ts_to_ns ---------------------------------------------------------- */

static void test_ts_to_ns_exact(void **state)
{
	struct timespec ts;
	ts = ts_make(0, 0);
	assert_i64_eq(tcs_ts_to_ns(&ts), 0);
	ts = ts_make(0, 999999999);
	assert_i64_eq(tcs_ts_to_ns(&ts), 999999999);
	ts = ts_make(1, 500);
	assert_i64_eq(tcs_ts_to_ns(&ts), 1000000500LL);
	ts = ts_make(1714564800, 250000000);
	assert_i64_eq(tcs_ts_to_ns(&ts), 1714564800250000000LL);
	ts = ts_make(MAX_EXACT_SEC - 2, 999999999);
	assert_i64_eq(tcs_ts_to_ns(&ts), 9223372033999999999LL);
}

/* "Saturating at TCS_NEVER": a value that fits in an int64_t comes back
 * exact; only values beyond it become TCS_NEVER. */
static void test_ts_to_ns_exact_near_top(void **state)
{
	struct timespec ts;
	ts = ts_make(MAX_EXACT_SEC - 1, 999999999);
	assert_i64_eq(tcs_ts_to_ns(&ts), 9223372034999999999LL);
	ts = ts_make(MAX_EXACT_SEC, 0);
	assert_i64_eq(tcs_ts_to_ns(&ts), 9223372035000000000LL);
	ts = ts_make(MAX_EXACT_SEC, 999999999);
	assert_i64_eq(tcs_ts_to_ns(&ts), 9223372035999999999LL);
	ts = ts_make(MAX_EXACT_SEC + 1, 0);
	assert_i64_eq(tcs_ts_to_ns(&ts), 9223372036000000000LL);
	ts = ts_make(MAX_EXACT_SEC + 1, 854775806);
	assert_i64_eq(tcs_ts_to_ns(&ts), TCS_NEVER - 1);
	/* and so ns -> timespec -> ns is the identity there too */
	for (int64_t ns = TCS_NEVER - 3000000000LL; ns < TCS_NEVER - 1000; ns += 99999989) {
		ts = tcs_ns_to_ts(ns);
		assert_i64_eq(tcs_ts_to_ns(&ts), ns);
	}
}

static void test_ts_to_ns_saturates(void **state)
{
	struct timespec ts;
	ts = ts_make(MAX_EXACT_SEC + 2, 0);
	assert_i64_eq(tcs_ts_to_ns(&ts), TCS_NEVER);
	ts = ts_make((time_t)INT64_MAX, 999999999);
	assert_i64_eq(tcs_ts_to_ns(&ts), TCS_NEVER);
	ts = ts_make((time_t)INT64_MAX, 0);
	assert_i64_eq(tcs_ts_to_ns(&ts), TCS_NEVER);
	ts = ts_make((time_t)INT64_MAX / 1000, 0);
	assert_i64_eq(tcs_ts_to_ns(&ts), TCS_NEVER);
	ts = ts_make((time_t)1 << 40, 0);
	assert_i64_eq(tcs_ts_to_ns(&ts), TCS_NEVER);
	/* INT64_MAX itself as a timespec is TCS_NEVER either way. */
	ts = ts_make(9223372036LL, 854775807L);
	assert_i64_eq(tcs_ts_to_ns(&ts), TCS_NEVER);
}

/* Around the top of the range the result is the exact value or TCS_NEVER,
 * never a wrapped (negative or small) number, and it never decreases. (Which
 * of the two for values that still fit is test_ts_to_ns_exact_near_top's
 * business.) */
static void test_ts_to_ns_boundary_sweep(void **state)
{
	static const long nsecs[] = { 0, 1, 854775806, 854775807, 854775808, 999999999 };
	int64_t last = -1;
	for (int64_t sec = MAX_EXACT_SEC - 3; sec <= MAX_EXACT_SEC + 3; sec++) {
		for (size_t i = 0; i < sizeof nsecs / sizeof nsecs[0]; i++) {
			struct timespec ts = ts_make((time_t)sec, nsecs[i]);
			__int128 exact = (__int128)sec * TCS_NS_PER_S + nsecs[i];
			int64_t got = tcs_ts_to_ns(&ts);
			if (sec < MAX_EXACT_SEC - 1)
				assert_i64_eq(got, (int64_t)exact);
			else if (exact > (__int128)INT64_MAX)
				assert_i64_eq(got, TCS_NEVER);
			else
				assert_true(got == (int64_t)exact || got == TCS_NEVER);
			assert_i64_ge(got, last);
			last = got;
		}
	}
}

/* ---- tcs_ns_to_ts / tcs_ns_to_tv ------------------------------------------- */

static void check_ts(int64_t ns, int64_t sec, long nsec)
{
	struct timespec ts = tcs_ns_to_ts(ns);
	if ((int64_t)ts.tv_sec != sec || ts.tv_nsec != nsec) {
		print_error("tcs_ns_to_ts(%lld) = {%lld, %ld}, expected {%lld, %ld}\n", (long long)ns,
			    (long long)ts.tv_sec, ts.tv_nsec, (long long)sec, nsec);
		fail();
	}
}

static void test_ns_to_ts_values(void **state)
{
	check_ts(0, 0, 0);
	check_ts(1, 0, 1);
	check_ts(999999999, 0, 999999999);
	check_ts(1000000000, 1, 0);
	check_ts(1999999999, 1, 999999999);
	check_ts(1714564800250000000LL, 1714564800, 250000000);
	check_ts(INT64_MAX, 9223372036LL, 854775807L);
	/* Negative values: floor division, tv_nsec always in [0, 1e9). */
	check_ts(-1, -1, 999999999);
	check_ts(-999999999, -1, 1);
	check_ts(-1000000000, -1, 0);
	check_ts(-1000000001, -2, 999999999);
	check_ts(-1500000000, -2, 500000000);
	check_ts(INT64_MIN, -9223372037LL, 145224192L);
}

static int64_t sample_ns(uint64_t *rng, int i)
{
	static const int64_t edges[] = { 0, 1, -1, 999, 1000, 999999999, 1000000000, -1000000000, INT64_MAX,
					 INT64_MIN, INT64_MAX - 1, INT64_MIN + 1, 9223372033999999999LL };
	if (i < (int)(sizeof edges / sizeof edges[0]))
		return edges[i];
	uint64_t r = test_rand(rng);
	switch (r & 3) {
	case 0:
		return (int64_t)test_rand(rng); /* anywhere */
	case 1:
		return (int64_t)(test_rand(rng) % 4000000000ULL) - 2000000000LL; /* a few seconds around 0 */
	case 2:
		return (int64_t)(test_rand(rng) >> 2); /* large positive */
	default:
		return -(int64_t)(test_rand(rng) >> 2); /* large negative */
	}
}

static void test_ns_to_ts_invariant(void **state)
{
	uint64_t rng = 0x9e3779b97f4a7c15ULL;
	for (int i = 0; i < 200000; i++) {
		int64_t ns = sample_ns(&rng, i);
		struct timespec ts = tcs_ns_to_ts(ns);
		assert_true(ts.tv_nsec >= 0 && ts.tv_nsec < TCS_NS_PER_S);
		__int128 back = (__int128)ts.tv_sec * TCS_NS_PER_S + ts.tv_nsec;
		assert_true(back == (__int128)ns);
	}
}

/* ns -> timespec -> ns is the identity for every non-negative value (the
 * values just below TCS_NEVER: test_ts_to_ns_exact_near_top). */
static void test_ns_ts_round_trip(void **state)
{
	uint64_t rng = 12345;
	for (int i = 0; i < 200000; i++) {
		int64_t ns = sample_ns(&rng, i);
		if (ns < 0 || ns >= 9223372034000000000LL - 1)
			continue;
		struct timespec ts = tcs_ns_to_ts(ns);
		assert_true(tcs_ts_valid(&ts));
		assert_i64_eq(tcs_ts_to_ns(&ts), ns);
	}
	struct timespec top = tcs_ns_to_ts(TCS_NEVER);
	assert_true(tcs_ts_valid(&top));
	assert_i64_eq(tcs_ts_to_ns(&top), TCS_NEVER);
}

static void check_tv(int64_t ns, int64_t sec, long usec)
{
	struct timeval tv = tcs_ns_to_tv(ns);
	if ((int64_t)tv.tv_sec != sec || (long)tv.tv_usec != usec) {
		print_error("tcs_ns_to_tv(%lld) = {%lld, %ld}, expected {%lld, %ld}\n", (long long)ns,
			    (long long)tv.tv_sec, (long)tv.tv_usec, (long long)sec, usec);
		fail();
	}
}

static void test_ns_to_tv_values(void **state)
{
	check_tv(0, 0, 0);
	check_tv(999, 0, 0);
	check_tv(1000, 0, 1);
	check_tv(1999, 0, 1);
	check_tv(999999999, 0, 999999);
	check_tv(1000000000, 1, 0);
	check_tv(1714564800250000000LL, 1714564800, 250000);
	check_tv(INT64_MAX, 9223372036LL, 854775);
	/* Negative: the microsecond value is rounded down (towards -inf). */
	check_tv(-1, -1, 999999);
	check_tv(-1000, -1, 999999);
	check_tv(-1001, -1, 999998);
	check_tv(-1000000000, -1, 0);
	check_tv(-1000000001, -2, 999999);
	check_tv(INT64_MIN, -9223372037LL, 145224);
}

static int64_t floor_div(int64_t a, int64_t b)
{
	int64_t q = a / b;
	return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

static void test_ns_to_tv_invariant_and_round_trip(void **state)
{
	uint64_t rng = 777;
	for (int i = 0; i < 200000; i++) {
		int64_t ns = sample_ns(&rng, i);
		struct timeval tv = tcs_ns_to_tv(ns);
		assert_true(tv.tv_usec >= 0 && tv.tv_usec < 1000000);
		__int128 us = (__int128)tv.tv_sec * 1000000 + tv.tv_usec;
		assert_true(us == (__int128)floor_div(ns, TCS_NS_PER_US));
		/* A whole number of microseconds survives ns -> tv -> ns. */
		int64_t whole = floor_div(ns, TCS_NS_PER_US);
		if (whole > INT64_MIN / 1000 && whole < INT64_MAX / 1000) {
			struct timeval tv2 = tcs_ns_to_tv(whole * 1000);
			__int128 back = ((__int128)tv2.tv_sec * 1000000 + tv2.tv_usec) * 1000;
			assert_true(back == (__int128)whole * 1000);
		}
	}
}

/* ---- tcs_ns_add ------------------------------------------------------------ */

static void test_ns_add_plain(void **state)
{
	assert_i64_eq(tcs_ns_add(0, 0), 0);
	assert_i64_eq(tcs_ns_add(1, 2), 3);
	assert_i64_eq(tcs_ns_add(1714564800000000000LL, 250000000), 1714564800250000000LL);
	assert_i64_eq(tcs_ns_add(TCS_NEVER - 2, 1), TCS_NEVER - 1);
	assert_i64_eq(tcs_ns_add(0, TCS_NEVER - 1), TCS_NEVER - 1);
}

static void test_ns_add_saturates(void **state)
{
	assert_i64_eq(tcs_ns_add(TCS_NEVER - 1, 1), TCS_NEVER);
	assert_i64_eq(tcs_ns_add(TCS_NEVER - 1, 2), TCS_NEVER);
	assert_i64_eq(tcs_ns_add(TCS_NEVER, 0), TCS_NEVER);
	assert_i64_eq(tcs_ns_add(TCS_NEVER, 1), TCS_NEVER);
	assert_i64_eq(tcs_ns_add(TCS_NEVER, TCS_NEVER), TCS_NEVER);
	assert_i64_eq(tcs_ns_add(0, TCS_NEVER), TCS_NEVER);
	assert_i64_eq(tcs_ns_add(1, TCS_NEVER), TCS_NEVER);
	assert_i64_eq(tcs_ns_add(5000000000000000000LL, 5000000000000000000LL), TCS_NEVER);
	/* A sleep of "forever" from any time is forever. */
	uint64_t rng = 99;
	for (int i = 0; i < 10000; i++) {
		int64_t a = (int64_t)(test_rand(&rng) >> 1);
		int64_t b = (int64_t)(test_rand(&rng) >> 1);
		__int128 exact = (__int128)a + b;
		int64_t got = tcs_ns_add(a, b);
		assert_i64_eq(got, exact >= (__int128)TCS_NEVER ? TCS_NEVER : (int64_t)exact);
		assert_i64_eq(tcs_ns_add(a, TCS_NEVER), TCS_NEVER);
	}
}

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
		cmocka_unit_test(test_ts_valid_accepts_valid),
		cmocka_unit_test(test_ts_valid_rejects_invalid),
		cmocka_unit_test(test_ts_to_ns_exact),
		cmocka_unit_test(test_ts_to_ns_exact_near_top),
		cmocka_unit_test(test_ts_to_ns_saturates),
		cmocka_unit_test(test_ts_to_ns_boundary_sweep),
		cmocka_unit_test(test_ns_to_ts_values),
		cmocka_unit_test(test_ns_to_ts_invariant),
		cmocka_unit_test(test_ns_ts_round_trip),
		cmocka_unit_test(test_ns_to_tv_values),
		cmocka_unit_test(test_ns_to_tv_invariant_and_round_trip),
		cmocka_unit_test(test_ns_add_plain),
		cmocka_unit_test(test_ns_add_saturates),
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
