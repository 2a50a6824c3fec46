// SensorModels (coordinator/sensor_models.h): what a sensor sees of a
// signal, checked against the laws it promises, on a made-up signal.
#include <cmath>
#include <cstdint>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "sensor_models.h"

namespace {

using tcs::SensorModel;
using tcs::SensorModels;

constexpr int64_t kMs = 1000000;

// The made-up world: signal 0's truth is its time in ms, signal 1 is 0.
void truth_at(int64_t t, size_t index, double *out)
{
	out[0] = index == 0 ? (double)t / kMs : 0.0;
}

// n steps of 1 ms from t = 0, what signal `index` reads after each.
std::vector<double> run(SensorModels &s, size_t index, int n)
{
	std::vector<double> seen;
	for (int i = 0; i <= n; i++) {
		int64_t t = i * kMs;
		s.observe(t, [t](size_t k, double *out) { truth_at(t, k, out); });
		std::vector<double> v;
		assert_true(s.read(index, v));
		seen.push_back(v.at(0));
	}
	return seen;
}

SensorModel model(size_t index)
{
	SensorModel m;
	m.signal = index == 0 ? "w.clock.position" : "w.zero.position";
	m.index = index;
	return m;
}

void no_model_reads_nothing(void **)
{
	SensorModels s({ model(1) }, 7);
	std::vector<double> v;
	assert_false(s.read(0, v));
	assert_false(s.read(5, v));
	assert_true(v.empty());
}

void latency_shows_an_older_value(void **)
{
	SensorModel m = model(0);
	m.latency_ns = 3 * kMs;
	SensorModels s({ m }, 7);
	std::vector<double> seen = run(s, 0, 10);
	// At t ms it reads t - 3 (the first 3 ms: the start's value).
	for (int t = 0; t <= 10; t++)
		assert_true(seen[(size_t)t] == std::max(0, t - 3));
}

void a_rate_holds_samples(void **)
{
	SensorModel m = model(0);
	m.period_ns = 4 * kMs; // 250 Hz at 1 ms steps
	m.bias = 0.5;
	SensorModels s({ m }, 7);
	std::vector<double> seen = run(s, 0, 10);
	for (int t = 0; t <= 10; t++)
		assert_true(seen[(size_t)t] == (t / 4) * 4 + 0.5);
}

void quantisation_is_on_the_grid(void **)
{
	SensorModel m = model(0);
	m.resolution = 3;
	SensorModels s({ m }, 7);
	std::vector<double> seen = run(s, 0, 10);
	for (int t = 0; t <= 10; t++)
		assert_true(seen[(size_t)t] == 3 * std::round(t / 3.0));
}

void noise_has_its_deviation_and_repeats_with_its_seed(void **)
{
	SensorModel m = model(1);
	m.noise = 0.01;
	const int n = 20000;
	SensorModels a({ m }, 42), b({ m }, 42), c({ m }, 43);
	std::vector<double> sa = run(a, 1, n), sb = run(b, 1, n), sc = run(c, 1, n);
	assert_true(sa == sb);
	assert_false(sa == sc);
	double sum = 0, sq = 0;
	for (double x : sa) {
		sum += x;
		sq += x * x;
	}
	const double mean = sum / (n + 1), sd = std::sqrt(sq / (n + 1) - mean * mean);
	// 20,001 draws: the sample deviation within 2 % (its own standard error
	// is 0.5 %), the mean within 4 standard errors.
	assert_true(std::fabs(sd / 0.01 - 1) < 0.02);
	assert_true(std::fabs(mean) < 4 * 0.01 / std::sqrt((double)n));
	// Quantised noise lands on the grid.
	m.resolution = 0.004;
	SensorModels q({ m }, 42);
	for (double x : run(q, 1, 1000))
		assert_true(std::fabs(x / 0.004 - std::round(x / 0.004)) < 1e-9);
}

void each_signal_has_its_own_stream(void **)
{
	// Adding a model on another signal changes nothing of this one's noise.
	SensorModel m = model(1);
	m.noise = 1;
	SensorModel other = model(0);
	other.noise = 1;
	SensorModels alone({ m }, 9), both({ other, m }, 9);
	assert_true(run(alone, 1, 100) == run(both, 1, 100));
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(no_model_reads_nothing),
		cmocka_unit_test(latency_shows_an_older_value),
		cmocka_unit_test(a_rate_holds_samples),
		cmocka_unit_test(quantisation_is_on_the_grid),
		cmocka_unit_test(noise_has_its_deviation_and_repeats_with_its_seed),
		cmocka_unit_test(each_signal_has_its_own_stream),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
