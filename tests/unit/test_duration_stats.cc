// Unit tests for common/duration_stats: exact extremes, a median
// within the histogram's resolution, constant memory whatever the count.
#include <cstdint>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "duration_stats.h"

namespace {

void empty_is_zero(void **)
{
	tcs::DurationStats s;
	assert_int_equal(s.count(), 0);
	assert_int_equal(s.min(), 0);
	assert_int_equal(s.median(), 0);
	assert_int_equal(s.max(), 0);
}

void one_value(void **)
{
	tcs::DurationStats s;
	s.add(12345);
	assert_int_equal(s.min(), 12345);
	assert_int_equal(s.median(), 12345); // clamped to the extremes
	assert_int_equal(s.max(), 12345);
}

void median_within_resolution(void **)
{
	// A skewed distribution, as step costs are: most near 1 us, a tail to 5 ms.
	tcs::DurationStats s;
	std::mt19937_64 rng(7);
	std::lognormal_distribution<double> d(std::log(1000.0), 0.6);
	std::vector<int64_t> all;
	for (int i = 0; i < 200001; i++) {
		int64_t v = (int64_t)d(rng);
		if (i % 1000 == 0)
			v = 5000000;
		all.push_back(v);
		s.add(v);
	}
	std::sort(all.begin(), all.end());
	double exact = (double)all[all.size() / 2];
	assert_int_equal(s.count(), all.size());
	assert_int_equal(s.min(), all.front());
	assert_int_equal(s.max(), all.back());
	assert_true(std::fabs((double)s.median() - exact) <= 0.022 * exact);
}

void negative_and_huge(void **)
{
	tcs::DurationStats s;
	s.add(-5); // a clock that went back counts as zero, never a crash
	s.add(INT64_MAX);
	assert_int_equal(s.min(), 0);
	assert_int_equal(s.max(), INT64_MAX);
	assert_true(s.median() >= 0);
}

} // namespace

int main()
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(empty_is_zero),
		cmocka_unit_test(one_value),
		cmocka_unit_test(median_within_resolution),
		cmocka_unit_test(negative_and_huge),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
