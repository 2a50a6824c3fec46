// Asleep in the kernel outside the hooks (asleep.cc), as functions over the
// run's state (run.h).
#pragma once

#include "run.h"

namespace tcs {

void arm_watchdog(Run &run, Controller &c);
void on_watchdog(Run &run, Lane &lane);
bool look_at(Run &run, Controller &c);
bool step_aside_if_asleep(Run &run, Controller &c);
bool still_asleep(Run &run, Controller &c, int64_t at);
void wake_from_asleep(Run &run, Controller &c);

} // namespace tcs
