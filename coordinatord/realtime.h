// Precise preemption where the system allows it: the coordinator runs
// SCHED_FIFO above its controllers, all pinned to one core. Where that is
// not permitted, one warning and normal scheduling; CPU accounting stays
// exact either way, only the overshoot of each budget grows.
#pragma once

#include <string>

namespace tcs {

struct RealtimePlan {
	bool fifo = false;      // SCHED_FIFO granted
	int controller_prio = 0;
	int cpu = -1;           // the core everything is pinned to, or -1
	std::string warning;    // non-empty: say it once
};

// Applies the plan to the calling process (the coordinator) before any
// controller is spawned; children inherit the core.
RealtimePlan setup_realtime(bool want_fifo);

// In a freshly forked controller, before exec: one priority below the
// coordinator. Async-signal-safe.
void apply_controller_realtime(const RealtimePlan &plan);

} // namespace tcs
