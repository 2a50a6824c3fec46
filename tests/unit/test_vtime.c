/* Unit tests for tcs/vtime.h, shared by the preload and the coordinator:
 * its time conversions (timespec and timeval to and from nanoseconds,
 * validity, saturating addition). Virtual time from CPU time is
 * test_vtime_cpu.c's. */
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
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
