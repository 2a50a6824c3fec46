// What a stop costs the process stopped: the kernel's work in that process
// to take SIGSTOP and, continued, to return from it, which the kernel counts
// as the process's CPU (4 to 90 us a stop on the machines seen). A program
// on the robot is never stopped, so tcs leaves this out of what a stop's
// slice charges (slices.cc), as measured here on each kind of lane.
#pragma once

#include <cstdint>

#include "realtime.h"

namespace tcs {

struct StopCost {
	int64_t stop_ns = 0;     // charged to the slice a stop ends or holds
	int64_t continue_ns = 0; // charged to the slice after SIGCONT
};

// Measured on the coordinator's core and on another (the same figure where
// there is only one): cpu mode's; zero in lockstep.
struct StopCosts {
	StopCost home, other;
};

// A stand-in process, pinned to `core` (-1: anywhere) at the controllers'
// priority, stopped and continued as a controller would be from here, its
// own CPU-clock readings bracketing each stop: the mean of the middle of 31
// rounds. Zero when it cannot be measured (nothing left out then: never
// less than the program used). Takes some 5 ms.
StopCost measure_stop_cost(const RealtimePlan &plan, int core);

} // namespace tcs
