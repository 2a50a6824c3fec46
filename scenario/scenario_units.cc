// Durations, rates, bit rates, numbers, signal names, paths, interface
// names and commands as a scenario file writes them.
#include "scenario_units.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <utility>

namespace tcs {

namespace {

bool is_space(char c)
{
	return c == ' ' || c == '\t';
}

std::string_view trim(std::string_view s)
{
	while (!s.empty() && is_space(s.front()))
		s.remove_prefix(1);
	while (!s.empty() && is_space(s.back()))
		s.remove_suffix(1);
	return s;
}

bool is_digit(char c)
{
	return c >= '0' && c <= '9';
}

// Reads the longest number at the start of s (digits, fraction, exponent)
// without strtod, whose decimal point follows the locale. Returns the
// characters used, 0 if s does not start with a number.
size_t scan_number(std::string_view s, long double *out)
{
	size_t i = 0;
	long double mant = 0;
	int exp10 = 0;
	bool digits = false;
	for (; i < s.size() && is_digit(s[i]); i++, digits = true) {
		if (mant < 1e30L)
			mant = mant * 10 + (s[i] - '0');
		else
			exp10++; // beyond long double's precision anyway
	}
	if (i < s.size() && s[i] == '.') {
		for (i++; i < s.size() && is_digit(s[i]); i++, digits = true) {
			if (mant < 1e30L) {
				mant = mant * 10 + (s[i] - '0');
				exp10--;
			}
		}
	}
	if (!digits)
		return 0;
	// An exponent only counts with its digits: "1e" leaves "e" to the unit.
	if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
		size_t j = i + 1;
		int sign = 1;
		if (j < s.size() && (s[j] == '+' || s[j] == '-'))
			sign = s[j++] == '-' ? -1 : 1;
		if (j < s.size() && is_digit(s[j])) {
			int e = 0;
			for (; j < s.size() && is_digit(s[j]); j++)
				if (e < 10000)
					e = e * 10 + (s[j] - '0');
			exp10 += sign * e;
			i = j;
		}
	}
	if (exp10 < -4000 || exp10 > 4000)
		*out = exp10 < 0 ? 0 : HUGE_VALL;
	else
		*out = mant * std::pow(10.0L, (long double)exp10);
	return i;
}

// The number and the unit after it: "2.5 kHz" is 2.5 and "kHz".
bool split_quantity(std::string_view text, long double *value, std::string_view *unit)
{
	text = trim(text);
	size_t used = scan_number(text, value);
	if (used == 0)
		return false;
	*unit = trim(text.substr(used));
	return true;
}

std::string quoted(std::string_view s)
{
	return "'" + std::string(s) + "'";
}

} // namespace

Result<double> parse_plain_number(std::string_view text)
{
	long double v;
	std::string_view t = trim(text);
	if (scan_number(t, &v) != t.size() || t.empty() || !std::isfinite(v))
		return Error{ quoted(text) + " is not a number" };
	return (double)v;
}

Result<int64_t> parse_duration_ns(std::string_view text)
{
	long double v;
	std::string_view unit;
	if (!split_quantity(text, &v, &unit))
		return Error{ quoted(text) + " is not a duration (examples: 1ms, 500us, 0.01s)" };
	long double mult;
	if (unit == "s")
		mult = 1e9L;
	else if (unit == "ms")
		mult = 1e6L;
	else if (unit == "us" || unit == "\xc2\xb5s") // µs
		mult = 1e3L;
	else if (unit == "ns")
		mult = 1;
	else if (unit.empty())
		return Error{ quoted(text) + " needs a unit (ns, us, ms or s)" };
	else
		return Error{ quoted(text) + ": unknown unit " + quoted(unit) + " (use ns, us, ms or s)" };
	long double ns = v * mult;
	if (!(ns < 9.2e18L))
		return Error{ quoted(text) + " is too long" };
	return (int64_t)std::llroundl(ns);
}

Result<double> parse_rate_hz(std::string_view text)
{
	long double v;
	std::string_view unit;
	if (!split_quantity(text, &v, &unit))
		return Error{ quoted(text) + " is not a rate (examples: 1kHz, 500Hz, 2.5 kHz)" };
	long double mult;
	if (unit == "Hz")
		mult = 1;
	else if (unit == "kHz" || unit == "KHz")
		mult = 1e3L;
	else if (unit == "MHz")
		mult = 1e6L;
	else if (unit.empty())
		return Error{ quoted(text) + " needs a unit (Hz, kHz or MHz)" };
	else
		return Error{ quoted(text) + ": unknown unit " + quoted(unit) + " (use Hz, kHz or MHz)" };
	long double hz = v * mult;
	if (!(hz > 0))
		return Error{ quoted(text) + ": a rate must be positive" };
	if (hz > 1e9L)
		return Error{ quoted(text) + " is too fast (at most 1 GHz)" };
	// Slower, its period would not fit virtual time ("1e-4000 Hz" is
	// positive, and 0 as a double).
	if (hz < 1e-6L)
		return Error{ quoted(text) + " is too slow (at least 1e-6 Hz, one record in 11.6 days)" };
	return (double)hz;
}

int64_t rate_period_ns(double hz)
{
	return (int64_t)std::llround(1e9 / hz);
}

Result<int64_t> parse_bitrate(std::string_view text)
{
	long double v;
	std::string_view unit;
	if (!split_quantity(text, &v, &unit))
		return Error{ quoted(text) + " is not a bit rate (examples: 1Mbit/s, 500kbit/s, 125k)" };
	long double mult;
	if (unit == "bit/s")
		mult = 1;
	else if (unit == "kbit/s" || unit == "Kbit/s" || unit == "k" || unit == "K")
		mult = 1e3L;
	else if (unit == "Mbit/s" || unit == "M")
		mult = 1e6L;
	else if (unit.empty())
		return Error{ quoted(text) + " needs a unit (bit/s, kbit/s or Mbit/s)" };
	else
		return Error{ quoted(text) + ": unknown unit " + quoted(unit) + " (use bit/s, kbit/s or Mbit/s)" };
	long double bps = std::roundl(v * mult);
	if (!(bps >= 1))
		return Error{ quoted(text) + ": a bit rate must be at least 1 bit/s" };
	if (bps > 1e12L)
		return Error{ quoted(text) + " is too fast (at most 1 Tbit/s)" };
	return (int64_t)bps;
}

Result<int64_t> parse_clock_hz(std::string_view text)
{
	auto hz = parse_rate_hz(text);
	if (!hz)
		return hz.error();
	// The rate's own digits, not the double's: "3.4MHz" is 3400000.
	double whole = std::round(*hz);
	if (whole < 1)
		return Error{ quoted(text) + " is below 1 Hz" };
	return (int64_t)whole;
}

bool is_normal_absolute_path(std::string_view p)
{
	if (p.size() < 2 || p[0] != '/' || p.back() == '/')
		return false;
	size_t i = 1;
	while (i <= p.size()) {
		size_t j = p.find('/', i);
		if (j == std::string_view::npos)
			j = p.size();
		std::string_view part = p.substr(i, j - i);
		if (part.empty() || part == "." || part == "..")
			return false;
		i = j + 1;
	}
	return p.find('\0') == std::string_view::npos;
}

bool is_interface_name(std::string_view s)
{
	// IFNAMSIZ is 16 with the terminating NUL.
	if (s.empty() || s.size() > 15 || s == "." || s == "..")
		return false;
	for (char c : s)
		if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || is_digit(c) || c == '_' || c == '.' ||
		      c == '-'))
			return false;
	return true;
}

bool is_identifier(std::string_view s)
{
	if (s.empty() || is_digit(s[0]))
		return false;
	for (char c : s)
		if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || is_digit(c) || c == '_'))
			return false;
	return true;
}

std::string signal_fields_text()
{
	std::string out;
	for (std::string_view f : kSignalFields)
		out += (out.empty() ? "" : ", ") + std::string(f);
	return out;
}

std::optional<SignalParts> split_signal_name(std::string_view name)
{
	size_t first = name.find('.'), last = name.rfind('.');
	if (first == std::string_view::npos || first == last)
		return std::nullopt;
	SignalParts p{ name.substr(0, first), name.substr(first + 1, last - first - 1), name.substr(last + 1) };
	if (!is_identifier(p.model))
		return std::nullopt;
	if (std::find(std::begin(kSignalFields), std::end(kSignalFields), p.field) == std::end(kSignalFields))
		return std::nullopt;
	// The part comes from the model (a URDF joint may be "wrist-1"): any
	// printable ASCII but spaces, and no empty dot-separated piece.
	if (p.part.empty() || p.part.front() == '.' || p.part.back() == '.' ||
	    p.part.find("..") != std::string_view::npos)
		return std::nullopt;
	for (char c : p.part)
		if (c <= ' ' || c > '~')
			return std::nullopt;
	return p;
}

std::optional<IndexedSignal> split_signal_index(std::string_view name)
{
	if (name.empty() || name.back() != ']')
		return IndexedSignal{ name, -1 };
	size_t open = name.rfind('[');
	if (open == std::string_view::npos)
		return std::nullopt;
	std::string_view digits = name.substr(open + 1, name.size() - open - 2);
	// One or two digits, no leading zero: one spelling a value, as for paths.
	if (digits.empty() || digits.size() > 2 || (digits.size() > 1 && digits[0] == '0'))
		return std::nullopt;
	int index = 0;
	for (char c : digits) {
		if (!is_digit(c))
			return std::nullopt;
		index = index * 10 + (c - '0');
	}
	return IndexedSignal{ name.substr(0, open), index };
}

int signal_field_width(std::string_view field)
{
	if (field == "pose")
		return 7;
	if (field == "twist")
		return 6;
	if (field == "orientation")
		return 4;
	if (field == "angular_velocity" || field == "linear_acceleration" || field == "force" || field == "torque")
		return 3;
	if (field == "position" || field == "velocity" || field == "effort")
		return 2;
	if (field == "count" || field == "range")
		return 1;
	return 0;
}

Result<std::vector<std::string>> split_command(std::string_view command)
{
	std::vector<std::string> words;
	std::string word;
	bool in_word = false; // "" is a word too
	for (size_t i = 0; i < command.size(); i++) {
		char c = command[i];
		if (is_space(c) || c == '\n' || c == '\r') { // a TOML """string""" may span lines
			if (in_word)
				words.push_back(std::exchange(word, {}));
			in_word = false;
			continue;
		}
		in_word = true;
		if (c == '\'' || c == '"') {
			size_t j = i + 1;
			for (; j < command.size() && command[j] != c; j++) {
				// Inside double quotes a backslash escapes only " and \, as in sh.
				if (c == '"' && command[j] == '\\' && j + 1 < command.size() &&
				    (command[j + 1] == '"' || command[j + 1] == '\\'))
					j++;
				word += command[j];
			}
			if (j == command.size())
				return Error{ std::string("unterminated ") + (c == '"' ? "double" : "single") +
					      " quote in '" + std::string(command) + "'" };
			i = j;
		} else {
			word += c;
		}
	}
	if (in_word)
		words.push_back(std::move(word));
	return words;
}

} // namespace tcs
