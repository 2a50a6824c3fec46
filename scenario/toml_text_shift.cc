// toml_text_shift: see toml_text_shift.h.
#include "toml_text_shift.h"

#include <cstdint>

namespace tcs {

// toml++ 3.3 has undefined behaviour (a __builtin_unreachable, upstream
// issues 190 and 295) when it asks whether certain characters between
// U+0080 and U+FEFF are whitespace, which it does wherever one stands
// outside a string ("[é]", "x = 1§"). Above U+FEFF its answer is sound, so
// the text it parses has each such character c moved to U+F0000 + c
// (private use), and unshift() moves it back in everything read out.
// Malformed UTF-8 is left for toml++ to report, and U+FEFF stays: toml++
// reads it as a byte-order mark.
static constexpr uint32_t kShift = 0xF0000;

static void put_utf8(std::string &out, uint32_t c)
{
	if (c < 0x800) {
		out += (char)(0xC0 | c >> 6);
	} else if (c < 0x10000) {
		out += (char)(0xE0 | c >> 12);
		out += (char)(0x80 | (c >> 6 & 0x3F));
	} else {
		out += (char)(0xF0 | c >> 18);
		out += (char)(0x80 | (c >> 12 & 0x3F));
		out += (char)(0x80 | (c >> 6 & 0x3F));
	}
	out += (char)(0x80 | (c & 0x3F));
}

// The well-formed non-ASCII character at s[i] and its length, or 0.
static size_t get_utf8(std::string_view s, size_t i, uint32_t *c)
{
	auto cont = [&s](size_t k, unsigned lo = 0x80, unsigned hi = 0xBF) {
		return k < s.size() && (unsigned char)s[k] >= lo && (unsigned char)s[k] <= hi;
	};
	unsigned b = (unsigned char)s[i];
	if (b >= 0xC2 && b <= 0xDF && cont(i + 1)) {
		*c = (b & 0x1F) << 6 | (s[i + 1] & 0x3F);
		return 2;
	}
	if (b >= 0xE0 && b <= 0xEF && cont(i + 1, b == 0xE0 ? 0xA0 : 0x80, b == 0xED ? 0x9F : 0xBF) && cont(i + 2)) {
		*c = (b & 0x0F) << 12 | (s[i + 1] & 0x3F) << 6 | (s[i + 2] & 0x3F);
		return 3;
	}
	if (b >= 0xF0 && b <= 0xF4 && cont(i + 1, b == 0xF0 ? 0x90 : 0x80, b == 0xF4 ? 0x8F : 0xBF) && cont(i + 2) &&
	    cont(i + 3)) {
		*c = (b & 0x07) << 18 | (s[i + 1] & 0x3F) << 12 | (s[i + 2] & 0x3F) << 6 | (s[i + 3] & 0x3F);
		return 4;
	}
	return 0;
}

static bool shiftable(uint32_t c)
{
	return c >= 0x80 && c < 0xFEFF;
}

// The text toml++ may parse; nullopt, with its line, for a character in the
// range the shift uses (it would come back as another one).
std::optional<std::string> shift_for_toml(std::string_view s, int *bad_line)
{
	std::string out;
	out.reserve(s.size() + s.size() / 4);
	int line = 1;
	for (size_t i = 0; i < s.size();) {
		uint32_t c;
		size_t n = (unsigned char)s[i] >= 0x80 ? get_utf8(s, i, &c) : 0;
		if (n && c >= kShift && shiftable(c - kShift)) {
			*bad_line = line;
			return std::nullopt;
		}
		if (n && shiftable(c))
			put_utf8(out, c + kShift);
		else
			out.append(s.substr(i, n ? n : 1));
		line += s[i] == '\n';
		i += n ? n : 1;
	}
	return out;
}

std::string unshift(std::string_view s)
{
	std::string out;
	for (size_t i = 0; i < s.size();) {
		uint32_t c;
		size_t n = (unsigned char)s[i] >= 0xF0 ? get_utf8(s, i, &c) : 0;
		if (n && c >= kShift && shiftable(c - kShift))
			put_utf8(out, c - kShift);
		else
			out.append(s.substr(i, n ? n : 1));
		i += n ? n : 1;
	}
	return out;
}

} // namespace tcs
