// Devices: what a controller asks of them (device_requests.cc), as functions
// over the run's state (run.h).
#pragma once

#include "run.h"

namespace tcs {

void on_dev_open(Run &run, Controller &c, const ::tcs_msg &m);
void on_dev_sync(Run &run, Controller &c, const ::tcs_msg &m);
bool complete_sync(Run &run, Controller &c);
// c waits in a device read (c.sync) with signal timers due by `at`: a
// read's answer carries no signals (its result takes their place), so they
// are raised now, at their time, a handler running in the read's wait,
// which goes on (as with SA_RESTART). False if there is nothing to raise.
bool raise_timers_in_read(Controller &c, int64_t at);
void reply_now(Run &run, Controller &c, int64_t arg);
void restart_slice(Run &run, Controller &c, int64_t request_cpu);

} // namespace tcs
