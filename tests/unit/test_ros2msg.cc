// Unit tests for trace/ros2msg and trace/cdr_writer: messages written with
// CdrWriter decode field for field (alignment, strings, sequences, fixed
// and bounded arrays, nested types by full and bare name, constants and
// defaults read past), ROS 2's rosgraph_msgs/Clock with its nested
// builtin_interfaces/Time decodes, and each kind of bad definition or message
// is refused with an error that says what.
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

#include "cdr_writer.h"
#include "ros2msg.h"

namespace {

using tcs::JsonValue;

tcs::Ros2Msg parse_ok(const char *name, const char *text)
{
	auto r = tcs::ros2msg_parse(name, text);
	if (!r.ok()) {
		print_error("ros2msg_parse failed: %s\n", r.error().message.c_str());
		fail();
	}
	return std::move(*r);
}

JsonValue decode_ok(const tcs::Ros2Msg &m, const std::string &data)
{
	auto r = tcs::cdr_decode(m, data);
	if (!r.ok()) {
		print_error("cdr_decode failed: %s\n", r.error().message.c_str());
		fail();
	}
	return std::move(*r);
}

void expect_error(const tcs::Result<JsonValue> &r, const std::string &what)
{
	assert_false(r.ok());
	if (r.error().message.find(what) == std::string::npos) {
		print_error("error \"%s\" does not say \"%s\"\n", r.error().message.c_str(), what.c_str());
		fail();
	}
}

const char kDefinition[] = R"(# a comment line
int8 small
float64 big          # aligned to 8, past 7 bytes of padding
string name
uint16[3] fixed
Inner[] inners
pkg/msg/Inner one    # the same type by its full name
int32 LIMIT=5        # a constant: not a field
bool flag true       # a default: read past
float32[<=4] bounded
uint64 huge
================================================================================
MSG: pkg/Inner
uint8 a
int64 b
)";

std::string sample()
{
	std::string out;
	tcs::CdrWriter w(out);
	w.put<int8_t>(-3);
	w.put<double>(2.5);
	w.put_string("pendulum");
	for (uint16_t v : { 1, 2, 65535 })
		w.put<uint16_t>(v);
	w.put_count(2);
	for (int i = 0; i < 2; i++) {
		w.put<uint8_t>((uint8_t)(10 + i));
		w.put<int64_t>(-1000000000000LL * (i + 1));
	}
	w.put<uint8_t>(7);
	w.put<int64_t>(8);
	w.put_bool(true);
	w.put_count(1);
	w.put<float>(0.5f);
	w.put<uint64_t>(UINT64_MAX);
	w.finish();
	return out;
}

void test_fields_decode_as_written(void **)
{
	tcs::Ros2Msg m = parse_ok("pkg/msg/Outer", kDefinition);
	assert_int_equal(m.types.size(), 2);
	std::string data = sample();
	// int8 at 0, pad to 8, float64 at 8, string at 16: as the alignment rules say.
	assert_int_equal((unsigned char)data[4], 0xFD);
	JsonValue v = decode_ok(m, data);
	assert_int_equal(v.object.size(), 9);
	assert_int_equal(v.get_int("small"), -3);
	assert_true(v.get_number("big") == 2.5);
	assert_string_equal(std::string(v.get_string("name")).c_str(), "pendulum");
	const JsonValue *fixed = v.get("fixed");
	assert_int_equal(fixed->array.size(), 3);
	assert_int_equal(fixed->array[2].integer, 65535);
	const JsonValue *inners = v.get("inners");
	assert_int_equal(inners->array.size(), 2);
	assert_int_equal(inners->array[1].get_int("a"), 11);
	assert_true(inners->array[1].get_int("b") == -2000000000000LL);
	assert_int_equal(v.get("one")->get_int("b"), 8);
	assert_true(v.get_bool("flag"));
	assert_true(v.get("bounded")->array[0].number == 0.5);
	const JsonValue *huge = v.get("huge");
	assert_false(huge->is_integer); // (past int64: a number)
	assert_true(huge->number == 18446744073709551615.0);
	assert_null(v.get("LIMIT"));
}

void test_ros2_clock(void **)
{
	tcs::Ros2Msg m = parse_ok("rosgraph_msgs/msg/Clock", R"(builtin_interfaces/Time clock
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
)");
	std::string data;
	tcs::CdrWriter w(data);
	w.put<int32_t>(12);
	w.put<uint32_t>(345);
	w.finish();
	assert_int_equal(data.size(), 12);
	JsonValue v = decode_ok(m, data);
	assert_int_equal(v.get("clock")->get_int("sec"), 12);
	assert_int_equal(v.get("clock")->get_int("nanosec"), 345);
}

// An empty sequence is its count alone (no padding for elements it does
// not have), and a buffer reused for a shorter message holds it in its
// first size() bytes.
void test_empty_sequences_and_reused_buffers(void **)
{
	tcs::Ros2Msg m = parse_ok("p/C", "string path\nfloat64[] values\nbool malformed");
	std::string buf;
	for (int round = 0; round < 2; round++) {
		std::vector<double> values;
		if (round == 0)
			values = { 1.5, -0.25, 3.0 };
		tcs::CdrWriter w(buf);
		w.put_string("/dev/tcs/a/torque");
		w.put_count(values.size());
		w.put_array(values.data(), values.size());
		w.put_bool(round == 1);
		assert_true(buf.size() >= w.size());
		JsonValue v = decode_ok(m, std::string(w.view()));
		assert_int_equal(v.get("values")->array.size(), values.size());
		assert_true(v.get_bool("malformed") == (round == 1));
	}
}

void test_bad_definitions(void **)
{
	struct {
		const char *text, *what;
	} bad[] = {
		{ "int32", "line 1: a field without a name" },
		{ "Missing thing", "line 1: type 'Missing' is not defined" },
		{ "int32 a\n===\nint32 b", "line 3: a section that does not start with 'MSG: type'" },
		{ "int32[x] a", "not a number" },
		{ "int32[0] a", "out of range" },
		{ "int32[ a", "without its ']'" },
		{ "wstring w", "'wstring' is not supported" },
		{ "# nothing\n", "has no fields" },
	};
	for (const auto &b : bad) {
		auto r = tcs::ros2msg_parse("p/M", b.text);
		assert_false(r.ok());
		if (r.error().message.find(b.what) == std::string::npos) {
			print_error("\"%s\": \"%s\" does not say \"%s\"\n", b.text, r.error().message.c_str(), b.what);
			fail();
		}
	}
}

void test_bad_messages(void **)
{
	tcs::Ros2Msg m = parse_ok("pkg/msg/Outer", kDefinition);
	const std::string good = sample();
	expect_error(tcs::cdr_decode(m, ""), "no CDR header");
	expect_error(tcs::cdr_decode(m, std::string("\x00\x00\x00\x00", 4) + good.substr(4)), "not little-endian CDR");
	for (size_t n = 4; n < good.size(); n++) // cut anywhere: an error, never a read past it
		assert_false(tcs::cdr_decode(m, good.substr(0, n)).ok());
	// A sequence claiming more elements than there are bytes.
	tcs::Ros2Msg seq = parse_ok("p/S", "float64[] v");
	std::string lie;
	tcs::CdrWriter w(lie);
	w.put_count(1000000000);
	w.finish();
	expect_error(tcs::cdr_decode(seq, lie), "1000000000 elements, 0 bytes left");
	// A string longer than the message.
	tcs::Ros2Msg str = parse_ok("p/S", "string s");
	std::string long_string;
	tcs::CdrWriter ws(long_string);
	ws.put<uint32_t>(50);
	ws.finish();
	expect_error(tcs::cdr_decode(str, long_string), "a string of 50 bytes");
	// Types nested without end: refused at the depth bound.
	tcs::Ros2Msg loop = parse_ok("p/L", "L[] next\nint8 x");
	std::string deep;
	tcs::CdrWriter wd(deep);
	for (int i = 0; i < 40; i++)
		wd.put_count(1);
	wd.finish();
	expect_error(tcs::cdr_decode(loop, deep), "types nested deeper than 32");
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_fields_decode_as_written),
		cmocka_unit_test(test_ros2_clock),
		cmocka_unit_test(test_empty_sequences_and_reused_buffers),
		cmocka_unit_test(test_bad_definitions),
		cmocka_unit_test(test_bad_messages),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
