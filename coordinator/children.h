// Children of controllers (children.cc), as functions over the run's state
// (run.h).
#pragma once

#include "run.h"

namespace tcs {

void on_child(Run &run, Controller &parent, const ::tcs_msg &m, UniqueFd channel);
void on_forked(Run &run, Controller &c, const ::tcs_msg &m);
void on_exec_look(Run &run);
void child_settled(Run &run, Controller &parent);
bool has_real_time_child(Run &run, Controller &c);
void child_wait_begins(Run &run, Controller &c, const ::tcs_msg &m, Request *side);

} // namespace tcs
