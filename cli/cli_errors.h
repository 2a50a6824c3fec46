// How the command-line tools (tcs-run, tcs-trace, coordinatord) say what
// went wrong: one line on stderr, "PROG: what", and exit status 2; a
// mistake in the command line adds where the help is.
#pragma once

#include <string>

namespace tcs {

int report_error(const char *prog, const std::string &msg);
int report_usage_error(const char *prog, const std::string &msg);
// What getopt_long's ':' (a value missing) or '?' (an unknown option) was
// about, for report_usage_error.
std::string getopt_complaint(int opt, char **argv, int optind);

} // namespace tcs
