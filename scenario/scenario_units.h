// The small syntaxes inside a scenario file's strings: durations ("1ms",
// "250 us"), rates ("1kHz", "500Hz", "2.5 kHz") and the plain numbers in
// them, signal names, controller commands. Errors name the text but not
// its place: the scenario parser adds FILE:LINE.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "error.h"

namespace tcs {

// A non-negative decimal: "2", "2.5", ".5", "1e3", "2.5E-3". No sign: no
// duration or rate is negative.
Result<double> parse_plain_number(std::string_view text);

// A duration with its unit (ns, us, µs, ms, s; spaces allowed between),
// in nanoseconds. A bare number is refused: is "5" seconds or milliseconds?
Result<int64_t> parse_duration_ns(std::string_view text);

// A rate with its unit (Hz, kHz, MHz; "KHz" is read as kHz), in Hz:
// at most 1 GHz, so that its period is at least 1 ns, and at least 1e-6 Hz,
// so that its period (at most 1e15 ns) is far from overflowing.
Result<double> parse_rate_hz(std::string_view text);

// 1/hz rounded to the nearest nanosecond: 3 kHz gives 333333 ns.
int64_t rate_period_ns(double hz);

// Letters, digits and '_', not starting with a digit: a model's name, the
// first part of its signal names.
bool is_identifier(std::string_view s);

// The last part of every signal's name (DESIGN §4, §8): a joint's, a
// link's, then a sensor's of a robot file.
inline constexpr std::string_view kSignalFields[] = { "position", "velocity", "effort", "pose", "twist",
						      "orientation", "angular_velocity", "linear_acceleration",
						      "force", "torque", "count", "range" };
// "position, velocity, ..., range": for messages.
std::string signal_fields_text();

// A signal name's three parts; nullopt unless it has the form
// <model>.<part>.<field>: the model an identifier, the field one of
// kSignalFields, the part anything printable without spaces (it may
// contain dots: "arm.link.3.pose").
struct SignalParts {
	std::string_view model, part, field;
};
std::optional<SignalParts> split_signal_name(std::string_view name);

// A controller command split into words: on blanks and line breaks, with "double
// quotes" (in which \" and \\ escape) and 'single quotes' (no escapes)
// grouping words, as a shell would but without expansions.
Result<std::vector<std::string>> split_command(std::string_view command);

} // namespace tcs
