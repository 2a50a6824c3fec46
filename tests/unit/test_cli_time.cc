// Unit tests for cli/cli_time: the durations, epochs and numbers users type
// on the command line, and how durations are printed back.
#include <climits>
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <string>

extern "C" {
#include <cmocka.h>
}

#include "cli_time.h"

namespace {

constexpr int64_t S = 1000000000LL;

void expect_duration(const char *text, int64_t want)
{
	auto r = tcs::parse_duration(text);
	if (!r.ok()) {
		print_error("parse_duration(\"%s\") failed: %s\n", text, r.error().message.c_str());
		fail();
	}
	if (*r != want) {
		print_error("parse_duration(\"%s\") = %lld, expected %lld\n", text, (long long)*r, (long long)want);
		fail();
	}
}

void expect_duration_error(const char *text)
{
	auto r = tcs::parse_duration(text);
	if (r.ok()) {
		print_error("parse_duration(\"%s\") = %lld, expected an error\n", text, (long long)*r);
		fail();
	}
	// The message names what the user typed.
	assert_true(r.error().message.find("'" + std::string(text) + "'") != std::string::npos);
}

void expect_epoch(const char *text, int64_t want)
{
	auto r = tcs::parse_epoch(text);
	if (!r.ok()) {
		print_error("parse_epoch(\"%s\") failed: %s\n", text, r.error().message.c_str());
		fail();
	}
	if (*r != want) {
		print_error("parse_epoch(\"%s\") = %lld, expected %lld\n", text, (long long)*r, (long long)want);
		fail();
	}
}

void expect_epoch_error(const char *text)
{
	auto r = tcs::parse_epoch(text);
	if (r.ok()) {
		print_error("parse_epoch(\"%s\") = %lld, expected an error\n", text, (long long)*r);
		fail();
	}
	assert_false(r.error().message.empty());
}

void expect_positive(const char *text, double want)
{
	auto r = tcs::parse_positive(text);
	if (!r.ok()) {
		print_error("parse_positive(\"%s\") failed: %s\n", text, r.error().message.c_str());
		fail();
	}
	if (*r != want) {
		print_error("parse_positive(\"%s\") = %.17g, expected %.17g\n", text, *r, want);
		fail();
	}
}

void expect_positive_error(const char *text)
{
	auto r = tcs::parse_positive(text);
	if (r.ok()) {
		print_error("parse_positive(\"%s\") = %.17g, expected an error\n", text, *r);
		fail();
	}
	assert_false(r.error().message.empty());
}

void expect_format(int64_t ns, const char *want)
{
	std::string got = tcs::format_duration(ns);
	if (got != want) {
		print_error("format_duration(%lld) = \"%s\", expected \"%s\"\n", (long long)ns, got.c_str(), want);
		fail();
	}
}

// ---- parse_duration ----------------------------------------------------------

void test_duration_units(void **)
{
	expect_duration("10s", 10 * S);
	expect_duration("250ms", 250000000LL);
	expect_duration("1.5min", 90 * S);
	expect_duration("2h", 7200 * S);
	expect_duration("20us", 20000);
	expect_duration("5ns", 5);
	expect_duration("0.5s", S / 2);
	expect_duration("1.25ms", 1250000);
	expect_duration("100000h", 100000LL * 3600 * S);
}

void test_duration_bare_seconds(void **)
{
	expect_duration("3", 3 * S);
	expect_duration("0.001", 1000000);
	expect_duration("1.5", 1500000000LL);
	expect_duration("86400", 86400 * S);
	expect_duration("0.000000001", 1);
}

void test_duration_errors(void **)
{
	expect_duration_error("");
	expect_duration_error("abc");
	expect_duration_error("10x");
	expect_duration_error("-1s");
	expect_duration_error("-1");
	expect_duration_error("s");
	expect_duration_error("ms");
	expect_duration_error(".");
	expect_duration_error("10 s");
	expect_duration_error(" 10s");
	expect_duration_error("10s ");
	expect_duration_error("1e3");
	expect_duration_error("10sec");
	expect_duration_error("10S");
	expect_duration_error("1..5s");
	expect_duration_error("1.5.5s");
	expect_duration_error("+1s");
	expect_duration_error("3000000h"); // beyond what an int64 of ns holds
	expect_duration_error("99999999999999999999");
}

// ---- parse_epoch --------------------------------------------------------------

void test_epoch_rfc3339(void **)
{
	expect_epoch("1970-01-01T00:00:00Z", 0);
	expect_epoch("1970-01-01T00:00:01Z", S);
	expect_epoch("2024-05-01T12:00:00Z", 1714564800LL * S);
	expect_epoch("2024-02-29T00:00:00Z", 1709164800LL * S);
	expect_epoch("2000-03-01T00:00:00Z", 951868800LL * S);
	expect_epoch("2016-12-31T23:59:59Z", 1483228799LL * S);
	// RFC 3339 allows lower case and a space instead of the T.
	expect_epoch("2024-05-01t12:00:00z", 1714564800LL * S);
	expect_epoch("2024-05-01 12:00:00Z", 1714564800LL * S);
}

void test_epoch_fraction(void **)
{
	expect_epoch("2024-05-01T12:00:00.25Z", 1714564800LL * S + 250000000);
	expect_epoch("2024-05-01T12:00:00.5Z", 1714564800LL * S + 500000000);
	expect_epoch("2024-05-01T12:00:00.000000001Z", 1714564800LL * S + 1);
	expect_epoch("2024-05-01T12:00:00.123456789Z", 1714564800LL * S + 123456789);
	expect_epoch("1970-01-01T00:00:00.999Z", 999000000);
}

void test_epoch_offsets(void **)
{
	expect_epoch("2024-05-01T12:00:00+02:00", (1714564800LL - 7200) * S);
	expect_epoch("2024-05-01T12:00:00-05:30", (1714564800LL + 19800) * S);
	expect_epoch("2024-05-01T12:00:00+00:00", 1714564800LL * S);
	expect_epoch("2024-05-01T12:00:00-00:00", 1714564800LL * S);
	expect_epoch("2024-05-01T12:00:00.25+02:00", (1714564800LL - 7200) * S + 250000000);
	// The same instant written in three zones.
	auto a = tcs::parse_epoch("2024-05-01T12:00:00Z");
	auto b = tcs::parse_epoch("2024-05-01T14:00:00+02:00");
	auto c = tcs::parse_epoch("2024-05-01T06:30:00-05:30");
	assert_true(a.ok() && b.ok() && c.ok());
	assert_true(*a == *b && *b == *c);
}

void test_epoch_seconds(void **)
{
	expect_epoch("0", 0);
	expect_epoch("1714564800", 1714564800LL * S);
	expect_epoch("1714564800.5", 1714564800LL * S + 500000000);
	expect_epoch("1714564800.25", 1714564800LL * S + 250000000);
	expect_epoch("1.5", 1500000000LL);
}

void test_epoch_errors(void **)
{
	expect_epoch_error("");
	expect_epoch_error("abc");
	expect_epoch_error("-5");
	expect_epoch_error("1714564800x");
	expect_epoch_error("1714564800s");
	expect_epoch_error("2024-05-01");
	expect_epoch_error("2024-05-01T12:00:00");   // no zone
	expect_epoch_error("2024-05-01T12:00:00.25"); // no zone
	expect_epoch_error("2024-05-01T12:00Z");
	expect_epoch_error("2024-13-01T12:00:00Z"); // month 13
	expect_epoch_error("2024-00-01T12:00:00Z");
	expect_epoch_error("2024-05-00T12:00:00Z");
	expect_epoch_error("2024-05-32T12:00:00Z");
	expect_epoch_error("2024-05-01T24:00:00Z");
	expect_epoch_error("2024-05-01T12:60:00Z");
	expect_epoch_error("2024-05-01T12:00:61Z");
	expect_epoch_error("2024/05/01T12:00:00Z");
	expect_epoch_error("2024-5-01T12:00:00Z");
	expect_epoch_error("2024-05-01X12:00:00Z");
	expect_epoch_error("2024-05-01T12:00:00+2:00");
	expect_epoch_error("2024-05-01T12:00:00+02");
	expect_epoch_error("2024-05-01T12:00:00+0200");
	expect_epoch_error("2024-05-01T12:00:00+24:00");
	expect_epoch_error("2024-05-01T12:00:00+02:60");
	expect_epoch_error("2024-05-01T12:00:00Zjunk");
	expect_epoch_error("2024-05-01T12:00:00+02:00junk");
	expect_epoch_error("2024-05-01T12:00:00.Z");
	expect_epoch_error("2024-05-01T12:00:00 Z");
	expect_epoch_error("1969-12-31T23:59:59Z"); // before the epoch
	expect_epoch_error("9300000000");           // beyond what an int64 of ns holds
}

// Days that do not exist must not silently become other days.
void test_epoch_rejects_nonexistent_dates(void **)
{
	expect_epoch_error("2024-02-30T00:00:00Z");
	expect_epoch_error("2023-02-29T00:00:00Z"); // 2023 is not a leap year
	expect_epoch_error("2024-04-31T00:00:00Z");
	expect_epoch_error("2100-02-29T00:00:00Z"); // 2100 is not a leap year
}

// A date too far in the future for an int64 of nanoseconds is an error, as
// it is when given as seconds, not a wrapped-around number.
void test_epoch_rejects_overflow(void **)
{
	expect_epoch("2200-01-01T00:00:00Z", 7258118400LL * S);
	expect_epoch_error("2300-01-01T00:00:00Z");
	expect_epoch_error("9999-12-31T23:59:59Z");
}

// ---- parse_positive ------------------------------------------------------------

void test_positive(void **)
{
	expect_positive("3", 3.0);
	expect_positive("0.5", 0.5);
	expect_positive("1.25", 1.25);
	expect_positive("1000000", 1e6);
	expect_positive("0.001", 0.001);
	expect_positive_error("");
	expect_positive_error("0");
	expect_positive_error("0.0");
	expect_positive_error("-1");
	expect_positive_error("-0.5");
	expect_positive_error("abc");
	expect_positive_error("3x");
	expect_positive_error("3 ");
	expect_positive_error(" 3");
	expect_positive_error("1e3");
	expect_positive_error(".");
	expect_positive_error("1000001");
}

// ---- format_duration -----------------------------------------------------------

void test_format(void **)
{
	expect_format(0, "0 ns");
	expect_format(1, "1 ns");
	expect_format(999, "999 ns");
	expect_format(-5, "-5 ns");
	expect_format(1000, "1.000 us");
	expect_format(12000, "12.000 us");
	expect_format(12345, "12.345 us");
	expect_format(999999, "999.999 us");
	expect_format(1000000, "1.000 ms");
	expect_format(250000000, "250.000 ms");
	expect_format(1000000000, "1.000 s");
	expect_format(12345000000LL, "12.345 s");
	expect_format(90 * S, "90.000 s");
	expect_format(-1500000000LL, "-1.500 s");
	expect_format(-2500, "-2.500 us");
	expect_format(INT64_MAX, "9223372036.855 s");
}

// What format_duration prints, parse_duration reads back (to the printed precision).
void test_format_parse_round_trip(void **)
{
	static const int64_t values[] = { 0, 7, 999, 1000, 12345, 999999, 1000000, 250000000, 12345000000LL, 90 * S };
	for (int64_t ns : values) {
		std::string text = tcs::format_duration(ns);
		std::string compact;
		for (char ch : text)
			if (ch != ' ')
				compact += ch;
		auto r = tcs::parse_duration(compact);
		if (!r.ok()) {
			print_error("parse_duration(\"%s\") failed: %s\n", compact.c_str(), r.error().message.c_str());
			fail();
		}
		assert_int_equal(*r, ns);
	}
}

} // namespace

int main()
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_duration_units),
		cmocka_unit_test(test_duration_bare_seconds),
		cmocka_unit_test(test_duration_errors),
		cmocka_unit_test(test_epoch_rfc3339),
		cmocka_unit_test(test_epoch_fraction),
		cmocka_unit_test(test_epoch_offsets),
		cmocka_unit_test(test_epoch_seconds),
		cmocka_unit_test(test_epoch_errors),
		cmocka_unit_test(test_epoch_rejects_nonexistent_dates),
		cmocka_unit_test(test_epoch_rejects_overflow),
		cmocka_unit_test(test_positive),
		cmocka_unit_test(test_format),
		cmocka_unit_test(test_format_parse_round_trip),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
