// Peers on other hosts, both ends (remote.cc), as functions over the run's
// state (run.h).
#pragma once

#include "run.h"

namespace tcs {

void on_step_host(Run &run);
void on_step_agent(Run &run);
bool agents_answered(const Run &run);
void grant_now(Run &run);
void answer_grant(Run &run);
void word_of_controllers(Run &run);
void lose(Run &run, const std::string &why);

} // namespace tcs
