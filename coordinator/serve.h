// Serving (coordinatord): controllers that attach to a running world and
// leave it, a world held until those it expects are there, and the fds of
// the daemon's socket and clients in the run's one event loop
// (Coordinator's serving methods call these).
#pragma once

#include <functional>

#include "run.h"

namespace tcs {

// Starts a controller in the running world, at the world's time.
Result<AttachedController> attach(Run &run, const ControllerSpec &spec);
// While held, nothing runs and the world does not step.
void hold_world(Run &run, bool on);
// Sends signo to controller id for its caller (Ctrl-C at tcs-run).
void signal_controller(Run &run, int id, int signo);
// Its caller has gone: SIGTERM now, SIGKILL after the end's grace.
void end_controller(Run &run, int id);
// Another fd for the run's loop (a socket, a client).
Status watch(Run &run, int fd, std::function<void()> on_ready);
void unwatch(Run &run, int fd);
// A controller tcs started (not a child of one) by its id, or null.
Controller *top_level(Run &run, int id);
// Whether o is a descendant of controller root.
bool descends_from(const Run &run, const Controller &o, int root);

} // namespace tcs
