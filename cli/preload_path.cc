// find_preload(): TCS_PRELOAD, then the build tree, then the install tree
// (sbin, where coordinatord goes, is as deep as bin).
#include "preload_path.h"

#include <limits.h>
#include <stdlib.h>
#include <unistd.h>

namespace tcs {

#ifndef TCS_BIN_TO_PRELOAD
#error "meson defines TCS_BIN_TO_PRELOAD: the preload's path relative to bindir"
#endif

Result<std::string> find_preload()
{
	if (const char *env = getenv("TCS_PRELOAD"); env && *env) {
		if (access(env, R_OK) != 0)
			return errno_error(std::string("TCS_PRELOAD=") + env);
		return std::string(env);
	}
	char exe[PATH_MAX];
	if (!realpath("/proc/self/exe", exe))
		return errno_error("cannot find my own executable");
	std::string dir(exe);
	dir.resize(dir.rfind('/'));
	std::string candidates[] = {
		dir + "/../libtcs_preload/libtcs_preload.so", // build tree: tools/ or coordinatord/
		std::string(TCS_BIN_TO_PRELOAD).front() == '/' ? std::string(TCS_BIN_TO_PRELOAD)
							       : dir + "/" + TCS_BIN_TO_PRELOAD,
	};
	for (const auto &c : candidates) {
		char real[PATH_MAX];
		if (realpath(c.c_str(), real) && access(real, R_OK) == 0)
			return std::string(real);
	}
	return Error{ "cannot find libtcs_preload.so (looked at " + candidates[0] + " and " + candidates[1] +
		      "); set TCS_PRELOAD to its path" };
}

} // namespace tcs
