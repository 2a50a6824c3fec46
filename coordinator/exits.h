// A controller's end (exits.cc), as functions over the run's state (run.h).
#pragma once

#include "run.h"

namespace tcs {

int64_t exited_cpu(Run &run, const Controller &c);
void on_pidfd(Run &run, Controller &c);
void on_exit(Run &run, Controller &c, int wait_status);
void drop(Run &run, Controller &c, const std::string &why);

} // namespace tcs
