// Threads: their channels and waits beside the controller's (threads.cc), as
// functions over the run's state (run.h).
#pragma once

#include "run.h"

namespace tcs {

void hear_threads(Run &run, Controller &c);
void on_thread(Run &run, Controller &c, const ::tcs_msg &m, UniqueFd channel);
void thread_gone(Run &run, Controller &c, ThreadChannel *t);
bool side_wait(Run &run, Controller &c, const ::tcs_msg &m, int fd, pid_t tid);
bool wake_threads(Run &run, Controller &c, int64_t at);
void end_side_waits(Run &run, Controller &c);
void answer_side(Run &run, Controller &c, const Request &w);
bool block_if_all_waiting(Run &run, Controller &c);
void end_all_side_waits(Run &run, Controller &c);
int runnable_threads(Run &run, Controller &c, pid_t also);
// A request of c's not yet served: posted to its mailbox, or unread in one
// of its channels. The thread that sent it sleeps waiting for us: it is not
// asleep outside the hooks.
bool request_unread(const Controller &c);

} // namespace tcs
