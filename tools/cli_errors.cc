// report_error(), report_usage_error().
#include "cli_errors.h"

#include <cstdio>

namespace tcs {

int report_error(const char *prog, const std::string &msg)
{
	fprintf(stderr, "%s: %s\n", prog, msg.c_str());
	return 2;
}

int report_usage_error(const char *prog, const std::string &msg)
{
	fprintf(stderr, "%s: %s\nTry '%s --help' for more information.\n", prog, msg.c_str(), prog);
	return 2;
}

} // namespace tcs
