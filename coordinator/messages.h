// A controller's messages (messages.cc), as functions over the run's state
// (run.h).
#pragma once

#include "run.h"

namespace tcs {

// A message on the main channel (t == nullptr) or a thread's.
void on_channel(Run &run, Controller &c, ThreadChannel *t);
// A request, from a channel or c's mailbox (t == nullptr).
void on_request(Run &run, Controller &c, ThreadChannel *t, const ::tcs_msg &m, UniqueFd passed);
void on_message(Run &run, Controller &c, const ::tcs_msg &m, int fd, pid_t tid);
bool take_mailbox(Run &run, Controller &c);

} // namespace tcs
