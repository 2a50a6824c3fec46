// Signals between controllers (signals.cc), as functions over the run's state
// (run.h).
#pragma once

#include "run.h"

namespace tcs {

void on_kill(Run &run, Controller &c, const ::tcs_msg &m);

} // namespace tcs
