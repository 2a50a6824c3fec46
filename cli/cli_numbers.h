// Parsing the whole numbers users type (a --seed).
#pragma once

#include <cstdint>
#include <string>

#include "error.h"

namespace tcs {

// "42", "18446744073709551615": a decimal number from 0 to 2^64 - 1.
Result<uint64_t> parse_unsigned(const std::string &text);

} // namespace tcs
