// A workaround for toml++ 3.3: it has undefined behaviour (upstream issues
// 190 and 295) when asked whether certain characters between U+0080 and
// U+FEFF are whitespace. The scenario parser hands it text with each such
// character moved to U+F0000 + c, and moves them back in what it reads out.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace tcs {

// The text toml++ may parse; nullopt, with its line, for a character in the
// range the shift uses (it would come back as another one).
std::optional<std::string> shift_for_toml(std::string_view s, int *bad_line);
// The inverse, for keys, strings and messages read out of toml++.
std::string unshift(std::string_view s);

} // namespace tcs
