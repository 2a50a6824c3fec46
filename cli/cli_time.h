// Parsing and printing the times users type and read: durations ("10s",
// "250ms", "1.5min"), epochs (RFC 3339 or seconds since 1970).
#pragma once

#include <cstdint>
#include <string>
#include <utility>

#include "error.h"

namespace tcs {

// "10s", "250ms", "20us", "5ns", "1.5min", "2h", or a bare number of seconds.
Result<int64_t> parse_duration(const std::string &text);
// "2024-05-01T12:00:00Z", "2024-05-01T12:00:00.25+02:00", "1714564800", "1714564800.5".
Result<int64_t> parse_epoch(const std::string &text);
// "25ns,500ns" (two durations), or one for both ("0"), each at most max_ns.
Result<std::pair<int64_t, int64_t>> parse_duration_pair(const std::string &text, int64_t max_ns);
// A positive decimal number ("3", "0.5").
Result<double> parse_positive(const std::string &text);
// "12.345 s", "250.000 ms", "12.0 us": three significant decimals.
std::string format_duration(int64_t ns);
// One number through a printf format (" (%.1f Hz)").
std::string format_number(const char *printf_format, double value) __attribute__((format(printf, 1, 0)));

} // namespace tcs
