// What the attach protocol's tests share: a typical run request, and
// checks on requests and messages. Include after <cmocka.h>.
#pragma once

#include <cstring>
#include <string>

#include "attach_protocol.h"

namespace attach_checks {

inline tcs::RunRequest typical_run()
{
	tcs::RunRequest r;
	r.path = "/usr/local/bin/pendulum_pd";
	r.cwd = "/home/robot/work";
	r.argv = { "pendulum_pd", "--seconds", "10", "" };
	r.env = { "PATH=/usr/local/bin:/usr/bin", "HOME=/home/robot", "EMPTY=", "A==b" };
	r.cpu_scale = 3;
	return r;
}

inline void assert_same_run(const tcs::RunRequest &a, const tcs::RunRequest &b)
{
	assert_memory_equal(&a.cpu_scale, &b.cpu_scale, sizeof a.cpu_scale);
	assert_true(a.path == b.path);
	assert_true(a.cwd == b.cwd);
	assert_true(a.argv == b.argv);
	assert_true(a.env == b.env);
}

inline bool contains(const std::string &s, const char *part)
{
	if (s.find(part) != std::string::npos)
		return true;
	print_error("'%s' does not contain '%s'\n", s.c_str(), part);
	return false;
}

} // namespace attach_checks
