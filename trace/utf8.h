// utf8_length: where JSON's text is checked (the parser) and written (the
// escaper), one reading of what valid UTF-8 is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace tcs {

// The length of the valid UTF-8 sequence at s[i] (1 to 4), or 0 when the
// bytes there are not one: overlong forms, surrogates and code points past
// U+10FFFF are invalid too.
inline size_t utf8_length(std::string_view s, size_t i)
{
	const auto at = [&](size_t k) { return i + k < s.size() ? uint8_t(s[i + k]) : 0; };
	const uint8_t c = at(0);
	if (c < 0x80)
		return 1;
	size_t n;
	uint8_t lo = 0x80, hi = 0xBF; // the second byte's range
	if (c >= 0xC2 && c <= 0xDF) {
		n = 2;
	} else if (c >= 0xE0 && c <= 0xEF) {
		n = 3;
		if (c == 0xE0)
			lo = 0xA0; // overlong
		else if (c == 0xED)
			hi = 0x9F; // surrogates
	} else if (c >= 0xF0 && c <= 0xF4) {
		n = 4;
		if (c == 0xF0)
			lo = 0x90; // overlong
		else if (c == 0xF4)
			hi = 0x8F; // past U+10FFFF
	} else {
		return 0;
	}
	if (at(1) < lo || at(1) > hi)
		return 0;
	for (size_t k = 2; k < n; k++)
		if (at(k) < 0x80 || at(k) > 0xBF)
			return 0;
	return n;
}

} // namespace tcs
