// Signal timers (signal_timers.cc), as functions over the run's state (run.h).
#pragma once

#include "run.h"

namespace tcs {

void on_timer(Run &run, Controller &c, const ::tcs_msg &m);
void budget_to_next_timer(Run &run, Controller &c);

} // namespace tcs
