// A small JSON parser (RFC 8259) for the messages of a trace. Untrusted
// input: nesting depth is bounded, numbers that are integers keep all 64
// bits, strings are checked to be UTF-8 after unescaping, and every error is
// a value saying at which byte it went wrong.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "error.h"

namespace tcs {

struct JsonValue {
	// Declared, not implicit: clang (14, with libstdc++ 12) otherwise
	// loops between this constructor and std::pair<std::string,
	// JsonValue>'s traits and rejects the type as incomplete.
	JsonValue() = default;

	enum class Type : uint8_t { Null, Bool, Number, String, Array, Object };
	Type type = Type::Null;
	bool boolean = false;
	double number = 0;       // any Number
	bool is_integer = false; // a Number written without fraction or exponent that fits int64
	int64_t integer = 0;     // when is_integer
	std::string string;
	std::vector<JsonValue> array;
	std::vector<std::pair<std::string, JsonValue>> object; // in file order

	// The member named key of an Object (the first, if repeated); null if
	// absent or not an Object.
	const JsonValue *get(std::string_view key) const;
	// Convenience for typed fields: the member as an integer / number /
	// string / bool, or fallback when absent or of another type.
	int64_t get_int(std::string_view key, int64_t fallback = 0) const;
	double get_number(std::string_view key, double fallback = 0) const;
	std::string_view get_string(std::string_view key, std::string_view fallback = "") const;
	bool get_bool(std::string_view key, bool fallback = false) const;
};

// Values to build a document with.
inline JsonValue json_integer(int64_t v)
{
	JsonValue j;
	j.type = JsonValue::Type::Number;
	j.number = (double)v;
	j.is_integer = true;
	j.integer = v;
	return j;
}
inline JsonValue json_number(double v)
{
	JsonValue j;
	j.type = JsonValue::Type::Number;
	j.number = v;
	return j;
}
inline JsonValue json_string(std::string_view v)
{
	JsonValue j;
	j.type = JsonValue::Type::String;
	j.string = std::string(v);
	return j;
}

// Parses one JSON text (surrounding whitespace allowed, nothing else).
// Errors: "at byte N: what is wrong".
Result<JsonValue> json_parse(std::string_view text);

} // namespace tcs

#include "json_write.h" // (the writer, for every reader of this header)
