// Devices: what a controller asks of them (device_requests.cc), as functions
// over the run's state (run.h).
#pragma once

#include "run.h"

namespace tcs {

void on_dev_open(Run &run, Controller &c, const ::tcs_msg &m);
void on_dev_sync(Run &run, Controller &c, const ::tcs_msg &m);
bool complete_sync(Run &run, Controller &c);
void reply_now(Run &run, Controller &c, int64_t arg);
void restart_slice(Run &run, Controller &c, int64_t request_cpu);

} // namespace tcs
