// Parsing whole numbers (cli_numbers.h): digits only, no sign, no
// overflow.
#include "cli_numbers.h"

namespace tcs {

Result<uint64_t> parse_unsigned(const std::string &text)
{
	Error bad{ "'" + text + "' is not a whole number from 0 to 18446744073709551615" };
	if (text.empty() || text.size() > 20)
		return bad;
	uint64_t v = 0;
	for (char ch : text) {
		if (ch < '0' || ch > '9')
			return bad;
		uint64_t digit = (uint64_t)(ch - '0');
		if (v > (UINT64_MAX - digit) / 10)
			return bad;
		v = v * 10 + digit;
	}
	return v;
}

} // namespace tcs
