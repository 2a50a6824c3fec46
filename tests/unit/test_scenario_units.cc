// Unit tests for scenario/scenario_units: durations, rates and plain
// numbers as scenario files and command lines write them, and a
// controller's command split into words.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "scenario_units.h"

namespace {

// ---- units ---------------------------------------------------------------------

void expect_ns(const char *text, int64_t want)
{
	auto r = tcs::parse_duration_ns(text);
	if (!r.ok() || *r != want) {
		print_error("parse_duration_ns(\"%s\"): %s, expected %lld\n", text,
			    r.ok() ? std::to_string(*r).c_str() : r.error().message.c_str(), (long long)want);
		fail();
	}
}

void expect_hz(const char *text, double hz, int64_t period)
{
	auto r = tcs::parse_rate_hz(text);
	if (!r.ok() || *r != hz || tcs::rate_period_ns(*r) != period) {
		print_error("parse_rate_hz(\"%s\"): %s, expected %g Hz\n", text,
			    r.ok() ? std::to_string(*r).c_str() : r.error().message.c_str(), hz);
		fail();
	}
}

void test_durations(void **)
{
	expect_ns("1ms", 1000000);
	expect_ns("250us", 250000);
	expect_ns("250 us", 250000);
	expect_ns("250\xc2\xb5s", 250000);
	expect_ns("2.5s", 2500000000LL);
	expect_ns("100ns", 100);
	expect_ns("0.5ms", 500000);
	expect_ns(".5ms", 500000);
	expect_ns("1e-3s", 1000000);
	expect_ns(" 1ms ", 1000000);
	for (const char *bad : { "", "5", "1.5", "fast", "ms", "5 sec", "5S", "-1ms", "+1ms", "1e", "1..5ms",
				 "1ms x", "99999999999s" }) {
		auto r = tcs::parse_duration_ns(bad);
		if (r.ok()) {
			print_error("parse_duration_ns(\"%s\") = %lld, expected an error\n", bad, (long long)*r);
			fail();
		}
		assert_true(r.error().message.find("'" + std::string(bad) + "'") != std::string::npos);
	}
}

void test_rates(void **)
{
	expect_hz("1kHz", 1000, 1000000);
	expect_hz("500Hz", 500, 2000000);
	expect_hz("2.5 kHz", 2500, 400000);
	expect_hz("1KHz", 1000, 1000000);
	expect_hz("3kHz", 3000, 333333);
	expect_hz("1MHz", 1e6, 1000);
	expect_hz("0.5Hz", 0.5, 2000000000LL);
	expect_hz("1e3Hz", 1000, 1000000);
	expect_hz("0.001Hz", 0.001, 1000000000000LL);
	expect_hz("1e-6Hz", 1e-6, 1000000000000000LL);
	// Positive but too slow: "11e-4000kHz" (found by scenario_fuzz) was 0 Hz
	// once made a double, with a period of llround(inf).
	for (const char *bad : { "", "fast", "1000", "0Hz", "0kHz", "2000MHz", "1 GHz", "1khz", "-5Hz", "Hz",
				 "11e-4000kHz", "1e-12 Hz", "0.0000009Hz" }) {
		auto r = tcs::parse_rate_hz(bad);
		if (r.ok()) {
			print_error("parse_rate_hz(\"%s\") = %g, expected an error\n", bad, *r);
			fail();
		}
	}
}

void test_plain_numbers(void **)
{
	assert_true(*tcs::parse_plain_number("2") == 2.0);
	assert_true(*tcs::parse_plain_number("2.5") == 2.5);
	assert_true(*tcs::parse_plain_number(" 0.25 ") == 0.25);
	assert_true(*tcs::parse_plain_number("1e3") == 1000.0);
	assert_true(*tcs::parse_plain_number("2.5E-1") == 0.25);
	for (const char *bad : { "", ".", "-1", "1x", "1 2", "e3", "1e999999" })
		assert_false(tcs::parse_plain_number(bad).ok());
}

// ---- a controller's command ------------------------------------------------------

void expect_words(const char *command, std::vector<std::string> want)
{
	auto r = tcs::split_command(command);
	if (!r.ok() || *r != want) {
		print_error("split_command(%s) gave %s\n", command,
			    r.ok() ? std::to_string(r->size()).c_str() : r.error().message.c_str());
		if (r.ok())
			for (const auto &w : *r)
				print_error("  [%s]\n", w.c_str());
		fail();
	}
}

void test_split_command(void **)
{
	expect_words("examples/pendulum_pd --rate 1000", { "examples/pendulum_pd", "--rate", "1000" });
	expect_words("  a \t b  ", { "a", "b" });
	expect_words("", {});
	expect_words("   ", {});
	expect_words("prog \"two words\" x", { "prog", "two words", "x" });
	expect_words("prog --name=\"a b\"c", { "prog", "--name=a bc" });
	expect_words("prog \"\" x", { "prog", "", "x" });
	expect_words("prog \"say \\\"hi\\\"\" \"back\\\\slash\" \"\\n\"", { "prog", "say \"hi\"", "back\\slash", "\\n" });
	expect_words("prog 'it \"is\" \\ raw'", { "prog", "it \"is\" \\ raw" });
	expect_words("prog a\\b", { "prog", "a\\b" });
	assert_false(tcs::split_command("prog \"open").ok());
	assert_false(tcs::split_command("prog 'open").ok());
	assert_false(tcs::split_command("prog \"ends in \\\"").ok());
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_durations),
		cmocka_unit_test(test_rates),
		cmocka_unit_test(test_plain_numbers),
		cmocka_unit_test(test_split_command),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
