// The JSON parser (RFC 8259) for trace messages.
#include "json.h"
#include "utf8.h"

#include <charconv>
#include <cstdio>

namespace tcs {

namespace {

// Deeper documents are refused: the parser recurses once per level, and
// nothing tcs writes nests more than a few levels.
constexpr int kMaxDepth = 64;


void append_utf8(std::string &out, uint32_t cp)
{
	if (cp < 0x80) {
		out += char(cp);
	} else if (cp < 0x800) {
		out += char(0xC0 | (cp >> 6));
		out += char(0x80 | (cp & 0x3F));
	} else if (cp < 0x10000) {
		out += char(0xE0 | (cp >> 12));
		out += char(0x80 | ((cp >> 6) & 0x3F));
		out += char(0x80 | (cp & 0x3F));
	} else {
		out += char(0xF0 | (cp >> 18));
		out += char(0x80 | ((cp >> 12) & 0x3F));
		out += char(0x80 | ((cp >> 6) & 0x3F));
		out += char(0x80 | (cp & 0x3F));
	}
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

class Parser {
public:
	explicit Parser(std::string_view text) : s_(text) {}

	Result<JsonValue> document()
	{
		JsonValue v;
		skip_space();
		if (!value(v, 0))
			return Error{ error_ };
		skip_space();
		if (pos_ < s_.size()) {
			fail(pos_, "unexpected " + describe(pos_) + " after the value");
			return Error{ error_ };
		}
		return v;
	}

private:
	bool fail(size_t at, const std::string &what)
	{
		error_ = "at byte " + std::to_string(at) + ": " + what;
		return false;
	}

	// The byte at i, for a message.
	std::string describe(size_t i) const
	{
		if (i >= s_.size())
			return "end of input";
		const uint8_t c = uint8_t(s_[i]);
		char buf[16];
		if (c >= 0x20 && c < 0x7F)
			snprintf(buf, sizeof buf, "'%c'", c);
		else
			snprintf(buf, sizeof buf, "byte 0x%02x", c);
		return buf;
	}

	void skip_space()
	{
		while (pos_ < s_.size() &&
		       (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\n' || s_[pos_] == '\r'))
			pos_++;
	}

	bool literal(std::string_view word)
	{
		if (s_.substr(pos_, word.size()) != word)
			return fail(pos_, "unexpected " + describe(pos_));
		pos_ += word.size();
		return true;
	}

	bool value(JsonValue &v, int depth)
	{
		if (pos_ >= s_.size())
			return fail(pos_, "unexpected end of input, expected a value");
		switch (s_[pos_]) {
		case '{':
		case '[':
			if (depth >= kMaxDepth)
				return fail(pos_, "nested more than " + std::to_string(kMaxDepth) + " levels deep");
			return s_[pos_] == '{' ? object(v, depth + 1) : array(v, depth + 1);
		case '"':
			v.type = JsonValue::Type::String;
			return string(v.string);
		case 't':
			v.type = JsonValue::Type::Bool;
			v.boolean = true;
			return literal("true");
		case 'f':
			v.type = JsonValue::Type::Bool;
			return literal("false");
		case 'n':
			return literal("null");
		default:
			if (s_[pos_] == '-' || is_digit(s_[pos_]))
				return number(v);
			return fail(pos_, "unexpected " + describe(pos_) + ", expected a value");
		}
	}

	bool array(JsonValue &v, int depth)
	{
		v.type = JsonValue::Type::Array;
		pos_++; // '['
		skip_space();
		if (pos_ < s_.size() && s_[pos_] == ']') {
			pos_++;
			return true;
		}
		for (;;) {
			v.array.emplace_back();
			if (!value(v.array.back(), depth))
				return false;
			skip_space();
			if (pos_ < s_.size() && s_[pos_] == ',') {
				pos_++;
				skip_space();
				continue;
			}
			if (pos_ < s_.size() && s_[pos_] == ']') {
				pos_++;
				return true;
			}
			return fail(pos_, "unexpected " + describe(pos_) + " in an array, expected ',' or ']'");
		}
	}

	bool object(JsonValue &v, int depth)
	{
		v.type = JsonValue::Type::Object;
		pos_++; // '{'
		skip_space();
		if (pos_ < s_.size() && s_[pos_] == '}') {
			pos_++;
			return true;
		}
		for (;;) {
			if (pos_ >= s_.size() || s_[pos_] != '"')
				return fail(pos_, "unexpected " + describe(pos_) + ", expected a member name");
			v.object.emplace_back();
			auto &member = v.object.back();
			if (!string(member.first))
				return false;
			skip_space();
			if (pos_ >= s_.size() || s_[pos_] != ':')
				return fail(pos_, "unexpected " + describe(pos_) + ", expected ':'");
			pos_++;
			skip_space();
			if (!value(member.second, depth))
				return false;
			skip_space();
			if (pos_ < s_.size() && s_[pos_] == ',') {
				pos_++;
				skip_space();
				continue;
			}
			if (pos_ < s_.size() && s_[pos_] == '}') {
				pos_++;
				return true;
			}
			return fail(pos_, "unexpected " + describe(pos_) + " in an object, expected ',' or '}'");
		}
	}

	// Four hex digits at pos_ (after "\u").
	bool hex4(uint32_t &cp)
	{
		cp = 0;
		for (int i = 0; i < 4; i++, pos_++) {
			if (pos_ >= s_.size())
				return fail(pos_, "unexpected end of input in a \\u escape");
			const char c = s_[pos_];
			int d = c >= '0' && c <= '9'   ? c - '0'
				: c >= 'a' && c <= 'f' ? c - 'a' + 10
				: c >= 'A' && c <= 'F' ? c - 'A' + 10
						       : -1;
			if (d < 0)
				return fail(pos_, "unexpected " + describe(pos_) + " in a \\u escape, expected a hex digit");
			cp = cp * 16 + uint32_t(d);
		}
		return true;
	}

	bool escape(std::string &out)
	{
		const size_t at = pos_; // the backslash
		pos_++;
		if (pos_ >= s_.size())
			return fail(pos_, "unexpected end of input in an escape");
		const char c = s_[pos_++];
		switch (c) {
		case '"': out += '"'; return true;
		case '\\': out += '\\'; return true;
		case '/': out += '/'; return true;
		case 'b': out += '\b'; return true;
		case 'f': out += '\f'; return true;
		case 'n': out += '\n'; return true;
		case 'r': out += '\r'; return true;
		case 't': out += '\t'; return true;
		case 'u': break;
		default: return fail(at, "invalid escape \\" + describe(pos_ - 1));
		}
		uint32_t cp;
		if (!hex4(cp))
			return false;
		if (cp >= 0xDC00 && cp <= 0xDFFF)
			return fail(at, "a \\u escape of a low surrogate without a high one before it");
		if (cp >= 0xD800 && cp <= 0xDBFF) {
			// UTF-16's pair for a code point past U+FFFF.
			if (s_.substr(pos_, 2) != "\\u")
				return fail(at, "a \\u escape of a high surrogate without a low one after it");
			pos_ += 2;
			uint32_t low;
			if (!hex4(low))
				return false;
			if (low < 0xDC00 || low > 0xDFFF)
				return fail(at, "a \\u escape of a high surrogate without a low one after it");
			cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
		}
		append_utf8(out, cp);
		return true;
	}

	bool string(std::string &out)
	{
		const size_t start = pos_;
		pos_++; // '"'
		for (;;) {
			if (pos_ >= s_.size())
				return fail(start, "unterminated string");
			const uint8_t c = uint8_t(s_[pos_]);
			if (c == '"') {
				pos_++;
				return true;
			}
			if (c == '\\') {
				if (!escape(out))
					return false;
			} else if (c < 0x20) {
				return fail(pos_, "control character 0x" + std::string(1, "0123456789abcdef"[c >> 4]) +
							  "0123456789abcdef"[c & 15] + " in a string (escape it)");
			} else {
				const size_t n = utf8_length(s_, pos_);
				if (n == 0)
					return fail(pos_, "invalid UTF-8 in a string");
				out.append(s_, pos_, n);
				pos_ += n;
			}
		}
	}

	bool number(JsonValue &v)
	{
		const size_t start = pos_;
		if (s_[pos_] == '-')
			pos_++;
		const size_t int_start = pos_;
		if (pos_ < s_.size() && s_[pos_] == '0') {
			pos_++;
		} else if (pos_ < s_.size() && is_digit(s_[pos_])) {
			while (pos_ < s_.size() && is_digit(s_[pos_]))
				pos_++;
		} else {
			return fail(pos_, "unexpected " + describe(pos_) + " in a number, expected a digit");
		}
		const size_t int_digits = pos_ - int_start;
		const bool int_zero = s_[int_start] == '0';
		bool integral = true;
		size_t frac_zeros = 0; // leading zeros of the fraction
		if (pos_ < s_.size() && s_[pos_] == '.') {
			integral = false;
			pos_++;
			if (pos_ >= s_.size() || !is_digit(s_[pos_]))
				return fail(pos_, "unexpected " + describe(pos_) + " after a decimal point, expected a digit");
			bool leading = true;
			for (; pos_ < s_.size() && is_digit(s_[pos_]); pos_++) {
				leading = leading && s_[pos_] == '0';
				frac_zeros += leading;
			}
		}
		int64_t exponent = 0;
		if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
			integral = false;
			pos_++;
			bool negative = false;
			if (pos_ < s_.size() && (s_[pos_] == '+' || s_[pos_] == '-'))
				negative = s_[pos_++] == '-';
			if (pos_ >= s_.size() || !is_digit(s_[pos_]))
				return fail(pos_, "unexpected " + describe(pos_) + " in an exponent, expected a digit");
			for (; pos_ < s_.size() && is_digit(s_[pos_]); pos_++)
				if (exponent < 1000000) // far beyond any double's; no overflow
					exponent = exponent * 10 + (s_[pos_] - '0');
			if (negative)
				exponent = -exponent;
		}

		const char *first = s_.data() + start, *last = s_.data() + pos_;
		v.type = JsonValue::Type::Number;
		auto [end, ec] = std::from_chars(first, last, v.number);
		if (ec == std::errc::result_out_of_range) {
			// Too small underflows to zero; too large is refused. The
			// decimal exponent of the leading digit tells which.
			const int64_t magnitude = exponent + (int_zero ? -int64_t(frac_zeros) : int64_t(int_digits));
			if (magnitude > 0)
				return fail(start, "number too large for a double");
			v.number = s_[start] == '-' ? -0.0 : 0.0;
		} else if (ec != std::errc() || end != last) {
			return fail(start, "malformed number");
		}
		if (integral) {
			auto [iend, iec] = std::from_chars(first, last, v.integer);
			v.is_integer = iec == std::errc() && iend == last;
			if (!v.is_integer)
				v.integer = 0;
		}
		return true;
	}

	std::string_view s_;
	size_t pos_ = 0;
	std::string error_;
};

} // namespace

Result<JsonValue> json_parse(std::string_view text)
{
	if (text.empty())
		return Error{ "at byte 0: empty input, expected a JSON value" };
	return Parser(text).document();
}


const JsonValue *JsonValue::get(std::string_view key) const
{
	if (type != Type::Object)
		return nullptr;
	for (const auto &[k, v] : object)
		if (k == key)
			return &v;
	return nullptr;
}

int64_t JsonValue::get_int(std::string_view key, int64_t fallback) const
{
	const JsonValue *v = get(key);
	return v && v->type == Type::Number && v->is_integer ? v->integer : fallback;
}

double JsonValue::get_number(std::string_view key, double fallback) const
{
	const JsonValue *v = get(key);
	return v && v->type == Type::Number ? v->number : fallback;
}

std::string_view JsonValue::get_string(std::string_view key, std::string_view fallback) const
{
	const JsonValue *v = get(key);
	return v && v->type == Type::String ? std::string_view(v->string) : fallback;
}

bool JsonValue::get_bool(std::string_view key, bool fallback) const
{
	const JsonValue *v = get(key);
	return v && v->type == Type::Bool ? v->boolean : fallback;
}

} // namespace tcs
