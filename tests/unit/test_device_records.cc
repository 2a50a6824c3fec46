// Unit tests for the device record formats (coordinator/device.h): text
// lines and little-endian f64s as a controller writes them to an actuator,
// incomplete and malformed records, and sensor records formatted and read
// back exactly. Inputs found by tests/fuzz/records_fuzz are kept here.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "device.h"
#include "tcs/record_check.h"

namespace {

using Records = std::vector<std::vector<double>>;

struct Parsed {
	bool ok;
	Records records;
	std::string left; // what stays for the next write
	std::string why;
};

Parsed parse(int format, size_t width, const std::string &bytes)
{
	Parsed p;
	p.left = bytes;
	p.ok = tcs::parse_records(format, width, p.left, p.records, &p.why);
	return p;
}

std::string f64s(const std::vector<double> &values)
{
	return tcs::format_record(TCS_FORMAT_BINARY, values);
}

void text_records(void **)
{
	Parsed p = parse(TCS_FORMAT_TEXT, 2, "1 2\n3,4\n\n \t\r\n5\t-6.5e-1\r\n7 8");
	assert_true(p.ok);
	assert_int_equal(p.records.size(), 3);
	assert_true(p.records[2][0] == 5 && p.records[2][1] == -0.65);
	assert_string_equal(p.left.c_str(), "7 8"); // its newline has not come yet
}

void text_malformed(void **)
{
	for (const char *bad : { "1 2\n", "x\n", "nan\n", "inf\n", "-inf\n", "1e999\n", "1 x\n" }) {
		Parsed p = parse(TCS_FORMAT_TEXT, 1, bad);
		assert_false(p.ok);
		assert_false(p.why.empty());
		assert_true(p.records.empty());
	}
	// The records before the malformed one are kept, the rest stays.
	Parsed p = parse(TCS_FORMAT_TEXT, 1, "1\nbad\n3\n");
	assert_false(p.ok);
	assert_int_equal(p.records.size(), 1);
	assert_string_equal(p.left.c_str(), "3\n");
}

void text_nul_byte(void **)
{
	// strtod stopped at the NUL and "0.5\0junk" passed for 0.5.
	Parsed p = parse(TCS_FORMAT_TEXT, 1, std::string("0.5\0junk\n", 9));
	assert_false(p.ok);
	assert_string_equal(p.why.c_str(), "a line holds a NUL byte");
	p = parse(TCS_FORMAT_TEXT, 2, std::string("1\0 2\n", 5));
	assert_false(p.ok);
	assert_true(p.records.empty());
}

void text_long_line(void **)
{
	// A line still without its newline past 4096 bytes is not a record.
	Parsed p = parse(TCS_FORMAT_TEXT, 1, std::string(4097, '1'));
	assert_false(p.ok);
	assert_true(p.left.empty());
	p = parse(TCS_FORMAT_TEXT, 1, std::string(4096, ' '));
	assert_true(p.ok);
	assert_int_equal(p.left.size(), 4096);
}

void binary_records(void **)
{
	Parsed p = parse(TCS_FORMAT_BINARY, 2, f64s({ 1, -2, 3.5, 4 }) + "abc");
	assert_true(p.ok);
	assert_int_equal(p.records.size(), 2);
	assert_true(p.records[1][0] == 3.5 && p.records[1][1] == 4);
	assert_string_equal(p.left.c_str(), "abc");
	for (double bad : { (double)NAN, (double)INFINITY, -(double)INFINITY }) {
		Parsed q = parse(TCS_FORMAT_BINARY, 1, f64s({ 1, bad, 3 }));
		assert_false(q.ok);
		assert_int_equal(q.records.size(), 1);
		assert_int_equal(q.left.size(), 8); // the record after it
	}
}

// A record formatted for a sensor reads back bit for bit, in both formats.
void round_trip(void **)
{
	const std::vector<double> values = { 0.1, -0.0, 5e-324, 1.7976931348623157e308, -2.5e-310, 1.0 / 3 };
	for (int format : { TCS_FORMAT_TEXT, TCS_FORMAT_BINARY }) {
		Parsed p = parse(format, values.size(), tcs::format_record(format, values));
		assert_true(p.ok);
		assert_int_equal(p.records.size(), 1);
		assert_memory_equal(p.records[0].data(), values.data(), values.size() * sizeof(double));
		assert_true(p.left.empty());
	}
	assert_string_equal(tcs::format_record(TCS_FORMAT_TEXT, { 0.75, -1 }).c_str(), "0.75 -1\n");
}

long checked(int format, size_t width, const std::string &bytes)
{
	return tcs_records_check(bytes.data(), bytes.size(), (uint32_t)format, (uint32_t)width);
}

// The preload's quick look (tcs/record_check.h): it vouches only for whole
// records the parser takes, and counts them; anything else is "unsure" (-1)
// and goes to the coordinator, which judges it.
void quick_check(void **)
{
	struct {
		size_t width;
		const char *text;
		long records;
	} cases[] = {
		{ 1, "1.5\n", 1 },
		{ 2, "1 2\n3,4\n\n \t\r\n+5\t-.65e-1\r\n", 3 },
		{ 1, "9e299\n0.000001e-99999\n", 2 }, // far from overflow; underflow is finite
		{ 1, "\n", 0 },          // nothing to vouch for
		{ 1, "2.", -1 },          // no newline: a piece
		{ 1, "0x1p1\n", -1 },     // strtod reads it; this does not try
		{ 1, "1e300\n", -1 },     // too near the end of the range to say
		{ 1, "99e299\n", -1 },
		{ 1, "1e999\n", -1 },
		{ 1, "1e\n", -1 },        // "1" then "e" to strtod
		{ 2, "1.5-2\n", -1 },     // two numbers to strtod, none here
		{ 1, "nan\n", -1 },
		{ 1, "abc\n", -1 },
		{ 1, "1 2\n", -1 },
		{ 1, ",,\n", -1 },        // no blank line to the parser
	};
	for (const auto &c : cases) {
		const std::string bytes = c.text;
		const long n = checked(TCS_FORMAT_TEXT, c.width, bytes);
		assert_int_equal(n, c.records);
		if (n >= 0) {
			Parsed p = parse(TCS_FORMAT_TEXT, c.width, bytes);
			assert_true(p.ok);
			assert_int_equal((long)p.records.size(), n);
			assert_true(p.left.empty());
		}
	}
	assert_int_equal(checked(TCS_FORMAT_TEXT, 1, std::string("1\0\n", 3)), -1);
	assert_int_equal(checked(TCS_FORMAT_BINARY, 2, f64s({ 1, 2, 3, 4 })), 2);
	assert_int_equal(checked(TCS_FORMAT_BINARY, 2, f64s({ 1, 2, 3 })), -1); // a piece
	assert_int_equal(checked(TCS_FORMAT_BINARY, 1, f64s({ 1, (double)NAN })), -1);
	assert_int_equal(checked(TCS_FORMAT_BINARY, 1, f64s({ -(double)INFINITY })), -1);
	assert_int_equal(checked(TCS_FORMAT_BINARY, 1, f64s({ 5e-324, -1.7976931348623157e308 })), 2);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(text_records),   cmocka_unit_test(text_malformed), cmocka_unit_test(text_nul_byte),
		cmocka_unit_test(text_long_line), cmocka_unit_test(binary_records), cmocka_unit_test(round_trip),
		cmocka_unit_test(quick_check),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
