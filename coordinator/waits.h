// Waits: BLOCK, EARLY, WAKE (waits.cc), as functions over the run's state
// (run.h).
#pragma once

#include "run.h"

namespace tcs {

void on_block(Run &run, Controller &c, const ::tcs_msg &m, int fd, pid_t tid);
void on_early(Run &run, Controller &c, const ::tcs_msg &m, int fd);
void send_wake(Run &run, Controller &c);
// c's request answered (owe_answer): now, unless c is
// Ready without being held (woken from asleep), when it goes with its
// resume.
void answer(Run &run, Controller &c);
void send_answer(Run &run, Controller &c, int fd, const ::tcs_msg &m, int pass_fd);

} // namespace tcs
