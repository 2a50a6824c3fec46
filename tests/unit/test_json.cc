// Unit tests for trace/json: valid documents (nesting, escapes,
// surrogate pairs, exact 64-bit integers), each kind of invalid one with
// the byte it names, the typed getters, and json_append_string read back
// by json_parse.
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

#include "json.h"

namespace {

using tcs::JsonValue;
using Type = tcs::JsonValue::Type;

JsonValue parse_ok(const std::string &text)
{
	auto r = tcs::json_parse(text);
	if (!r.ok()) {
		print_error("json_parse(%s) failed: %s\n", text.c_str(), r.error().message.c_str());
		fail();
	}
	return std::move(*r);
}

// The error is "at byte N: " followed by text containing what.
void expect_error(const std::string &text, size_t at, const std::string &what)
{
	auto r = tcs::json_parse(text);
	if (r.ok()) {
		print_error("json_parse(%s) succeeded; expected an error at byte %zu\n", text.c_str(), at);
		fail();
	}
	const std::string &m = r.error().message;
	const std::string prefix = "at byte " + std::to_string(at) + ": ";
	if (m.rfind(prefix, 0) != 0 || m.find(what, prefix.size()) == std::string::npos) {
		print_error("json_parse(%s): got '%s', expected '%s...%s...'\n", text.c_str(), m.c_str(), prefix.c_str(),
			    what.c_str());
		fail();
	}
}

void test_scalars(void **)
{
	assert_true(parse_ok("null").type == Type::Null);
	JsonValue t = parse_ok(" true ");
	assert_true(t.type == Type::Bool && t.boolean);
	JsonValue f = parse_ok("\t\r\nfalse\n");
	assert_true(f.type == Type::Bool && !f.boolean);
	JsonValue s = parse_ok("\"h\\u00e9llo\"");
	assert_true(s.type == Type::String);
	assert_string_equal(s.string.c_str(), "h\xc3\xa9llo");
}

void test_numbers(void **)
{
	// Beyond 2^53 a double loses the last digit; the integer keeps it.
	JsonValue big = parse_ok("9007199254740993");
	assert_true(big.type == Type::Number && big.is_integer);
	assert_true(big.integer == 9007199254740993);
	assert_true(big.number == 9007199254740992.0);
	JsonValue neg = parse_ok("-9223372036854775808");
	assert_true(neg.is_integer && neg.integer == INT64_MIN);
	JsonValue max = parse_ok("9223372036854775807");
	assert_true(max.is_integer && max.integer == INT64_MAX);
	// One past int64: a double only.
	JsonValue over = parse_ok("9223372036854775808");
	assert_false(over.is_integer);
	assert_true(over.number == 9223372036854775808.0);
	JsonValue zero = parse_ok("-0");
	assert_true(zero.is_integer && zero.integer == 0);

	struct {
		const char *text;
		double value;
	} floats[] = {
		{ "1.5", 1.5 },   { "-0.25", -0.25 }, { "1e3", 1000 },         { "1E+3", 1000 },
		{ "2.5e-3", 0.0025 }, { "0.1", 0.1 },   { "-12.5E2", -1250 }, { "1e-400", 0 },
		{ "123.0", 123 }, { "5e0", 5 },
	};
	for (const auto &c : floats) {
		JsonValue v = parse_ok(c.text);
		assert_true(v.type == Type::Number);
		assert_false(v.is_integer); // written with a fraction or exponent
		if (v.number != c.value) {
			print_error("%s parsed as %.17g\n", c.text, v.number);
			fail();
		}
	}
	expect_error("1e400", 0, "too large");
	expect_error("-1.5e99999999999999999999", 0, "too large");
	assert_true(parse_ok("0.0000000000000000000000000000000000001e-300").number == 0);
}

void test_nested(void **)
{
	JsonValue v = parse_ok(R"( {"a": [1, 2.5, "x", {"b": null}], "c": {"d": {"e": [[], {}]}}, "a": false} )");
	assert_true(v.type == Type::Object);
	assert_int_equal(v.object.size(), 3);
	assert_string_equal(v.object[2].first.c_str(), "a"); // repeated: both kept, in order
	const JsonValue *a = v.get("a");
	assert_non_null(a);
	assert_true(a->type == Type::Array); // the first one
	assert_int_equal(a->array.size(), 4);
	assert_int_equal(a->array[0].integer, 1);
	assert_true(a->array[1].number == 2.5);
	assert_string_equal(a->array[2].string.c_str(), "x");
	assert_true(a->array[3].get("b")->type == Type::Null);
	const JsonValue *e = v.get("c")->get("d")->get("e");
	assert_true(e->type == Type::Array && e->array.size() == 2);
	assert_true(e->array[1].type == Type::Object && e->array[1].object.empty());

	// 64 levels are fine, 65 are not.
	std::string deep = std::string(64, '[') + std::string(64, ']');
	parse_ok(deep);
	expect_error(std::string(65, '[') + std::string(65, ']'), 64, "nested more than 64 levels");
	std::string objects;
	for (int i = 0; i < 65; i++)
		objects += "{\"k\":";
	objects += "1" + std::string(65, '}');
	expect_error(objects, 64 * 5, "nested more than 64 levels");
	// Far deeper input fails as fast, without recursing further.
	expect_error(std::string(1 << 20, '['), 64, "nested");
}

void test_getters(void **)
{
	JsonValue v = parse_ok(R"({"i": 42, "f": 1.5, "s": "str", "b": true, "n": null, "big": 1e300})");
	assert_int_equal(v.get_int("i"), 42);
	assert_int_equal(v.get_int("f", -1), -1); // not an integer
	assert_int_equal(v.get_int("missing", 7), 7);
	assert_true(v.get_number("i") == 42);
	assert_true(v.get_number("f") == 1.5);
	assert_true(v.get_number("s", 3) == 3);
	assert_true(v.get_number("big") == 1e300);
	assert_string_equal(std::string(v.get_string("s")).c_str(), "str");
	assert_string_equal(std::string(v.get_string("i", "none")).c_str(), "none");
	assert_true(v.get_bool("b"));
	assert_true(v.get_bool("n", true));
	assert_null(v.get("nothing"));
	JsonValue arr = parse_ok("[1]");
	assert_null(arr.get("0"));
	assert_int_equal(arr.get_int("0", 5), 5);
}

void test_strings(void **)
{
	JsonValue v = parse_ok(R"("q\"b\\s\/n\nr\rt\tb\bf\f")");
	assert_string_equal(v.string.c_str(), "q\"b\\s/n\nr\rt\tb\bf\f");
	// A surrogate pair: U+1F600 as UTF-16, and as UTF-8 directly.
	assert_string_equal(parse_ok(R"("\ud83d\ude00")").string.c_str(), "\xf0\x9f\x98\x80");
	assert_string_equal(parse_ok("\"\xf0\x9f\x98\x80\"").string.c_str(), "\xf0\x9f\x98\x80");
	assert_string_equal(parse_ok(R"("\uDBFF\uDFFF")").string.c_str(), "\xf4\x8f\xbf\xbf");
	assert_string_equal(parse_ok(R"("\u20AC\u0041")").string.c_str(), "\xe2\x82\xac" "A");
	JsonValue nul = parse_ok(R"("a\u0000b")");
	assert_int_equal(nul.string.size(), 3);
	assert_int_equal(nul.string[1], 0);
}

void test_invalid(void **)
{
	expect_error("", 0, "empty input");
	expect_error("   ", 3, "end of input");
	expect_error("[1,2,]", 5, "unexpected ']'");
	expect_error("{\"a\":1,}", 7, "expected a member name");
	expect_error("\"abc", 0, "unterminated string");
	expect_error("[\"abc]", 1, "unterminated string");
	expect_error(R"("a\x")", 2, "invalid escape");
	expect_error(R"("a\u12G4")", 6, "hex digit");
	expect_error(R"("\u12)", 5, "end of input");
	expect_error(R"("\ud83d")", 1, "high surrogate without a low one");
	expect_error(R"("\ud83dx")", 1, "high surrogate without a low one");
	expect_error(R"("\ud83d\u0041")", 1, "high surrogate without a low one");
	expect_error(R"("x\ude00")", 2, "low surrogate");
	expect_error("\"a\nb\"", 2, "control character 0x0a");
	expect_error(std::string("\"a\0b\"", 5), 2, "control character 0x00");
	expect_error("\"\xff\"", 1, "invalid UTF-8");
	expect_error("\"\xc0\xaf\"", 1, "invalid UTF-8");         // overlong '/'
	expect_error("\"\xed\xa0\x80\"", 1, "invalid UTF-8");     // a surrogate in UTF-8
	expect_error("\"\xf4\x90\x80\x80\"", 1, "invalid UTF-8"); // past U+10FFFF
	expect_error("\"\xe2\x82\"", 1, "invalid UTF-8");         // cut short
	expect_error("{} x", 3, "after the value");
	expect_error("1 2", 2, "after the value");
	expect_error("nul", 0, "unexpected 'n'");
	expect_error("truex", 4, "after the value");
	expect_error("01", 1, "after the value");
	expect_error("-", 1, "expected a digit");
	expect_error("1.", 2, "after a decimal point");
	expect_error("1e+", 3, "exponent");
	expect_error("+1", 0, "expected a value");
	expect_error(".5", 0, "expected a value");
	expect_error("{\"a\" 1}", 5, "expected ':'");
	expect_error("{1:2}", 1, "member name");
	expect_error("[1 2]", 3, "expected ',' or ']'");
	expect_error("{\"a\":1 \"b\":2}", 7, "expected ',' or '}'");
	expect_error("[", 1, "end of input");
	expect_error("NaN", 0, "unexpected 'N'");
	expect_error("\xef\xbb\xbf{}", 0, "byte 0xef"); // no byte order mark
}

// Whatever the text, json_append_string writes a literal json_parse reads
// back as the same text (valid UTF-8), or with U+FFFD for bytes that are not.
void test_append_string(void **)
{
	std::vector<std::string> texts = { "", "plain", "quote\" backslash\\ slash/", "\n\r\t\b\f",
					   std::string("nul\0byte", 8), "\x01\x1f\x7f", "\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80" };
	std::string all;
	for (int c = 0; c < 0x80; c++)
		all += char(c);
	texts.push_back(all);
	for (const std::string &t : texts) {
		std::string out = "x";
		tcs::json_append_string(out, t);
		assert_int_equal(out[0], 'x');
		JsonValue v = parse_ok(out.substr(1));
		assert_true(v.type == Type::String);
		assert_true(v.string == t);
	}
	std::string out;
	tcs::json_append_string(out, "a\"\\\n\x01");
	assert_string_equal(out.c_str(), "\"a\\\"\\\\\\n\\u0001\"");
	out.clear();
	tcs::json_append_string(out, "bad\xff\xc3");
	assert_string_equal(out.c_str(), "\"bad\\ufffd\\ufffd\"");
	assert_string_equal(parse_ok(out).string.c_str(), "bad\xef\xbf\xbd\xef\xbf\xbd");
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_scalars),  cmocka_unit_test(test_numbers), cmocka_unit_test(test_nested),
		cmocka_unit_test(test_getters),  cmocka_unit_test(test_strings), cmocka_unit_test(test_invalid),
		cmocka_unit_test(test_append_string),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
