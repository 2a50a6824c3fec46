// The time syntax of the command line.
#include "cli_time.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace tcs {

namespace {

// Parses a non-negative decimal at the start of s (no sign, no exponent);
// returns the characters used, 0 if none.
size_t parse_decimal(const char *s, long double *out)
{
	size_t i = 0;
	long double v = 0;
	bool digits = false;
	while (s[i] >= '0' && s[i] <= '9') {
		v = v * 10 + (s[i++] - '0');
		digits = true;
	}
	if (s[i] == '.') {
		long double scale = 0.1L;
		i++;
		while (s[i] >= '0' && s[i] <= '9') {
			v += (s[i++] - '0') * scale;
			scale /= 10;
			digits = true;
		}
	}
	if (!digits)
		return 0;
	*out = v;
	return i;
}

bool parse_fixed(const char *s, int len, int *out)
{
	int v = 0;
	for (int i = 0; i < len; i++) {
		if (s[i] < '0' || s[i] > '9')
			return false;
		v = v * 10 + (s[i] - '0');
	}
	*out = v;
	return true;
}

// Days from 1970-01-01 to y-m-d (proleptic Gregorian).
int64_t days_from_civil(int64_t y, unsigned m, unsigned d)
{
	y -= m <= 2;
	const int64_t era = (y >= 0 ? y : y - 399) / 400;
	const unsigned yoe = (unsigned)(y - era * 400);
	const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
	const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
	return era * 146097 + (int64_t)doe - 719468;
}

} // namespace

Result<int64_t> parse_duration(const std::string &text)
{
	long double v;
	size_t used = parse_decimal(text.c_str(), &v);
	if (used == 0)
		return Error{ "'" + text + "' is not a duration (examples: 10s, 250ms, 1.5min)" };
	std::string unit = text.substr(used);
	long double mult;
	if (unit.empty() || unit == "s")
		mult = 1e9L;
	else if (unit == "ms")
		mult = 1e6L;
	else if (unit == "us")
		mult = 1e3L;
	else if (unit == "ns")
		mult = 1;
	else if (unit == "min" || unit == "m")
		mult = 60e9L;
	else if (unit == "h")
		mult = 3600e9L;
	else
		return Error{ "'" + text + "': unknown unit '" + unit + "' (use ns, us, ms, s, min or h)" };
	long double ns = v * mult;
	if (ns > 9.2e18L)
		return Error{ "'" + text + "' is too long" };
	return (int64_t)std::llroundl(ns);
}

Result<std::pair<int64_t, int64_t>> parse_duration_pair(const std::string &text, int64_t max_ns)
{
	size_t comma = text.find(',');
	auto first = parse_duration(text.substr(0, comma));
	if (!first)
		return first.error();
	auto second = comma == std::string::npos ? first : parse_duration(text.substr(comma + 1));
	if (!second)
		return second.error();
	if (*first > max_ns || *second > max_ns)
		return Error{ "'" + text + "': at most " + format_duration(max_ns) + " each" };
	return std::pair{ *first, *second };
}

Result<double> parse_positive(const std::string &text)
{
	long double v;
	size_t used = parse_decimal(text.c_str(), &v);
	if (used == 0 || used != text.size() || v <= 0 || v > 1e6L)
		return Error{ "'" + text + "' is not a positive number" };
	return (double)v;
}

Result<int64_t> parse_epoch(const std::string &text)
{
	const char *s = text.c_str();
	Error bad{ "'" + text + "' is not an epoch (RFC 3339 such as 2024-05-01T12:00:00Z, or seconds since 1970)" };
	long double secs;
	size_t used = parse_decimal(s, &secs);
	if (used == text.size() && used > 0) {
		if (secs > 9.2e9L)
			return bad;
		return (int64_t)std::llroundl(secs * 1e9L);
	}
	int y, mo, d, h, mi, se;
	if (text.size() < 20 || !parse_fixed(s, 4, &y) || s[4] != '-' || !parse_fixed(s + 5, 2, &mo) || s[7] != '-' ||
	    !parse_fixed(s + 8, 2, &d) || (s[10] != 'T' && s[10] != 't' && s[10] != ' ') ||
	    !parse_fixed(s + 11, 2, &h) || s[13] != ':' || !parse_fixed(s + 14, 2, &mi) || s[16] != ':' ||
	    !parse_fixed(s + 17, 2, &se))
		return bad;
	static const int month_days[] = { 31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31 };
	bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
	if (mo < 1 || mo > 12 || d < 1 || d > month_days[mo - 1] || (mo == 2 && d == 29 && !leap) || h > 23 ||
	    mi > 59 || se > 60 || y < 1970 || y > 2262)
		return bad;
	const char *p = s + 19;
	int64_t frac_ns = 0;
	if (*p == '.') {
		long double frac;
		size_t n = parse_decimal(p, &frac);
		if (n < 2)
			return bad;
		frac_ns = (int64_t)std::llroundl(frac * 1e9L);
		p += n;
	}
	int64_t offset = 0;
	if (*p == 'Z' || *p == 'z') {
		p++;
	} else if (*p == '+' || *p == '-') {
		int oh, om;
		if (!parse_fixed(p + 1, 2, &oh) || p[3] != ':' || !parse_fixed(p + 4, 2, &om) || oh > 23 || om > 59)
			return bad;
		offset = (*p == '+' ? 1 : -1) * (int64_t)(oh * 3600 + om * 60);
		p += 6;
	} else {
		return bad;
	}
	if (*p != '\0')
		return bad;
	int64_t t = days_from_civil(y, (unsigned)mo, (unsigned)d) * 86400 + h * 3600 + mi * 60 + se - offset;
	if (t < 0 || t > 9200000000LL) // beyond int64 nanoseconds (2262)
		return bad;
	return t * 1000000000LL + frac_ns;
}

std::string format_duration(int64_t ns)
{
	char buf[64];
	double v = (double)ns;
	// Choose the unit after rounding to three decimals: 999999999 ns is 1.000 s.
	if (ns >= 999999500LL || ns <= -999999500LL)
		snprintf(buf, sizeof buf, "%.3f s", v / 1e9);
	else if (ns >= 1000000 || ns <= -1000000)
		snprintf(buf, sizeof buf, "%.3f ms", v / 1e6);
	else if (ns >= 1000 || ns <= -1000)
		snprintf(buf, sizeof buf, "%.3f us", v / 1e3);
	else
		snprintf(buf, sizeof buf, "%lld ns", (long long)ns);
	return buf;
}

std::string format_number(const char *printf_format, double value)
{
	char buf[128];
	snprintf(buf, sizeof buf, printf_format, value);
	return buf;
}

} // namespace tcs
