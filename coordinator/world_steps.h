// The world's steps, as scheduler.h decides (world_steps.cc), as functions
// over the run's state (run.h).
#pragma once

#include "run.h"

namespace tcs {

void schedule(Run &run);
bool run_best(Run &run, Controller &best, int64_t at, int64_t until);
Contender contender_of(const Run &run, const Controller &c);
bool advance_to(Run &run, int64_t next);
int64_t next_run_at(const Run &run, const Controller &c);
void on_idle(Run &run);
void arm_idle_step(Run &run);
void apply_commands(Run &run, int64_t boundary);
Status step_world(Run &run);

} // namespace tcs
