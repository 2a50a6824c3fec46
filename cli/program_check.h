// Before anything starts: find the program as execvp would, and refuse one
// that libtcs_preload could not hook (static, another architecture, setuid),
// following #! interpreters, rather than let it run in real time.
#pragma once

#include <string>

#include "error.h"

namespace tcs {

// The path execvp would run for name; an error naming the cause otherwise.
Result<std::string> resolve_program(const std::string &name);
// Ok if the dynamic loader will load libtcs_preload into path.
Status check_preloadable(const std::string &path);

} // namespace tcs
