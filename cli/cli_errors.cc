// report_error(), report_usage_error().
#include "cli_errors.h"

#include <cstdio>

#include "tcs/clock_page.h"

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

std::string getopt_complaint(int opt, char **argv, int optind)
{
	if (opt == ':')
		return std::string("option '") + argv[optind - 1] + "' needs a value";
	return std::string("unknown option '") + argv[optind - 1] + "'";
}

} // namespace tcs
