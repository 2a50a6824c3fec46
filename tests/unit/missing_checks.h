// What a cmocka test needs and lacks here (a folder of files beside the
// project): under CI a failure naming it and how to get it, since a CI
// machine lacking it would otherwise go green without the check; elsewhere
// a skip whose reason is the line printed just before cmocka's
// "[  SKIPPED ]", which tools/test_summary.py lists. The rule of
// tests/process/harness.py's missing(). Include after <cmocka.h>.
#pragma once

#include <cstdlib>
#include <strings.h>

namespace missing_checks {

// A CI run: CI set (CI services set CI=true; .ci/run does too) to anything
// but empty, 0 or false (harness.py's under_ci()).
inline bool under_ci()
{
	const char *ci = getenv("CI");
	return ci && *ci && strcasecmp(ci, "0") != 0 && strcasecmp(ci, "false") != 0;
}

// Ends the test: what (absent here) and how to get it.
inline void missing(const char *what, const char *how)
{
	if (under_ci())
		fail_msg("%s: %s (a failure, not a skip, under CI=%s)", what, how, getenv("CI"));
	print_message("%s: %s\n", what, how);
	skip();
}

} // namespace missing_checks
