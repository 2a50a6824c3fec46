/* A quick look at actuator records on the controller's side: whether bytes
 * about to be written are whole records that the coordinator's parser
 * (coordinator/device.cc, parse_records) will surely take. In lockstep the
 * preload sends such a write on without a round trip, and the coordinator
 * takes it at the controller's next request; a write this cannot vouch for
 * goes to the coordinator at once, which decides (EINVAL or not), as ever.
 *
 * So it may say "unsure" of a good record (a hex float, an exponent near
 * the range's end, numbers with no space between them) but must never vouch
 * for one the parser refuses: tests/fuzz/records_fuzz checks that. Pure C
 * without libc, as it runs inside a hook: strtod would follow the
 * program's locale, the coordinator's does not. */
#ifndef TCS_RECORD_CHECK_H
#define TCS_RECORD_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "device_table.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One number of the plain kind: [+-] digits [. digits] [e [+-] digits], at
 * least one digit before the exponent, and far from overflowing a double.
 * Returns the length taken, or 0 if it is not such a number. */
static inline size_t tcs_plain_number(const char *s, size_t n)
{
	size_t i = 0, digits = 0, int_digits = 0;
	int leading = 1;
	if (i < n && (s[i] == '+' || s[i] == '-'))
		i++;
	for (; i < n && s[i] >= '0' && s[i] <= '9'; i++, digits++)
		if (!(leading && s[i] == '0')) {
			leading = 0;
			int_digits++;
		}
	if (i < n && s[i] == '.')
		for (i++; i < n && s[i] >= '0' && s[i] <= '9'; i++)
			digits++;
	if (digits == 0)
		return 0;
	long exp = 0;
	if (i < n && (s[i] == 'e' || s[i] == 'E')) {
		size_t j = i + 1, exp_digits = 0;
		int neg = 0;
		if (j < n && (s[j] == '+' || s[j] == '-'))
			neg = s[j++] == '-';
		for (; j < n && s[j] >= '0' && s[j] <= '9'; j++, exp_digits++)
			if (exp_digits < 6)
				exp = exp * 10 + (s[j] - '0');
		if (exp_digits == 0 || exp_digits > 5)
			return 0; /* "1e" is "1" then "e" to strtod; a huge exponent: unsure */
		exp = neg ? -exp : exp;
		i = j;
	}
	/* Below 10^(int_digits + exp) <= 10^300 < DBL_MAX: finite. Underflow
	 * gives 0 or a subnormal, which is finite too. */
	if ((long)int_digits + exp > 300)
		return 0;
	return i;
}

static inline int tcs_record_separator(char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == ',';
}

/* How many whole records buf holds, if all of them surely parse; -1 if
 * unsure (or malformed: the coordinator then says which). */
static inline long tcs_records_check(const void *buf, size_t n, uint32_t format, uint32_t width)
{
	const unsigned char *b = (const unsigned char *)buf;
	if (width == 0 || n == 0)
		return -1;
	if (format == TCS_FORMAT_BINARY) {
		if (n % (8 * (size_t)width) != 0)
			return -1;
		for (size_t i = 0; i < n; i += 8) {
			/* little-endian: the exponent's bits are in bytes 6 and 7 */
			unsigned e = ((unsigned)(b[i + 7] & 0x7f) << 4) | (b[i + 6] >> 4);
			if (e == 0x7ff)
				return -1; /* not finite */
		}
		return (long)(n / (8 * (size_t)width));
	}
	if (format != TCS_FORMAT_TEXT || b[n - 1] != '\n')
		return -1;
	const char *s = (const char *)buf;
	long records = 0;
	for (size_t i = 0; i < n;) {
		uint32_t values = 0, commas = 0;
		for (;;) {
			for (; tcs_record_separator(s[i]); i++)
				commas += s[i] == ',';
			if (s[i] == '\n')
				break;
			size_t len = tcs_plain_number(s + i, n - i);
			if (len == 0)
				return -1;
			i += len;
			if (s[i] != '\n' && !tcs_record_separator(s[i]))
				return -1; /* "1.5-2", "3x": strtod's business */
			values++;
		}
		i++; /* the newline */
		if (values == 0 && commas == 0)
			continue; /* a blank line carries nothing (",," is no blank line) */
		if (values != width)
			return -1;
		records++;
	}
	return records;
}

#ifdef __cplusplus
}
#endif
#endif
