// What tcs-run tells the user about a run: the progress line, the summary
// at the end, and the exit status (docs/DESIGN.md §5).
#pragma once

#include <cstdint>
#include <string>

#include "coordinator.h"

namespace tcs {

std::string progress_line(int64_t virtual_ns, int64_t wall_ns);
// Each line begins "who: ".
std::string summary(const RunReport &r, int mode, const std::string &who = "tcs-run");
// What --quiet still says: each controller tcs dropped, and why, a line each.
std::string drops(const RunReport &r, const std::string &who = "tcs-run");
// The controller's status (128+N for signal N), 0 when the duration ended
// the run, 128+N when signal N ended tcs-run, 2 if tcs dropped a controller.
int exit_status(const RunReport &r);
// A wait status as an exit status: its code, or 128+N for signal N.
int status_code(int wait_status);

} // namespace tcs
