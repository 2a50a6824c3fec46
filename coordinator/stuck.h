// Controllers stuck in tcs's own hands: a thread of one waits for an
// answer to a request the coordinator does not hold (stuck.cc).
#pragma once

#include "run.h"

namespace tcs {

// Looks at every controller (from the progress timer); one stuck for
// kStuckAfter of wall time is dropped with a message that says so.
void look_for_stuck(Run &run);

} // namespace tcs
