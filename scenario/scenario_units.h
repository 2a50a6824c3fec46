// The small syntaxes inside a scenario file's strings: durations ("1ms",
// "250 us"), rates ("1kHz", "500Hz", "2.5 kHz"), bit rates ("1Mbit/s") and
// the plain numbers in them, signal names, paths, interface names,
// controller commands. Errors name the text but not its place: the
// scenario parser adds FILE:LINE.
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

// A bit rate with its unit (bit/s, kbit/s, Mbit/s; "Kbit/s" is read as
// kbit/s; "500k" and "1M" as ip-link's users write them), in whole bit/s,
// rounded: "83.333kbit/s", a CAN rate, is 83333. From 1 bit/s to 1 Tbit/s;
// a bus's own range is its parser's.
Result<int64_t> parse_bitrate(std::string_view text);

// A clock's frequency: a rate as parse_rate_hz reads it, in whole Hz,
// rounded ("3.4MHz" is 3400000); at least 1 Hz.
Result<int64_t> parse_clock_hz(std::string_view text);

// Absolute, and spelled one way only (no ., .., // or trailing /), so that
// comparing strings finds every duplicate device path.
bool is_normal_absolute_path(std::string_view p);

// A name Linux takes for a network interface ("can0"): 1 to 15 of
// A-Z a-z 0-9 _ . -, and not "." or "..".
bool is_interface_name(std::string_view s);

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

// One value of a signal, as a CAN frame's field carries it:
// "<signal>[index]" ("pendulum.rod.pose[2]": z), or "<signal>" alone
// (index -1). nullopt for a malformed index ("x[", "x[a]", "x[01]").
struct IndexedSignal {
	std::string_view signal;
	int index = -1;
};
std::optional<IndexedSignal> split_signal_index(std::string_view name);

// How many values a signal of this field has at most: a pose 7 (x y z
// qw qx qy qz), a twist 6, an orientation 4, the vectors 3, a joint's
// position, velocity and effort 2 (a universal joint's two axes), a count
// or range 1. 0 for a field that is not in kSignalFields.
int signal_field_width(std::string_view field);

// A controller command split into words: on blanks and line breaks, with "double
// quotes" (in which \" and \\ escape) and 'single quotes' (no escapes)
// grouping words, as a shell would but without expansions.
Result<std::vector<std::string>> split_command(std::string_view command);

} // namespace tcs
