// ODE's process-wide and per-thread initialisation, done on first use.
#pragma once

#include "error.h"

namespace tcs::sim {

// Initialises ODE once per process and its per-thread data once per
// calling thread. Call before any ODE use on a thread (create and step may
// be called from different threads over a world's life).
Status ode_ready();

} // namespace tcs::sim
