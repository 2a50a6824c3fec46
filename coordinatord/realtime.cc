// setup_realtime(): SCHED_FIFO and core pinning, with a clear fallback.
#include "realtime.h"

#include <sched.h>

#include <cerrno>
#include <cstring>

namespace tcs {

namespace {
// Low real-time priorities: above every normal task, below the kernel's
// own threaded interrupt handlers (50), which must keep running.
constexpr int kCoordinatorPrio = 3;
constexpr int kControllerPrio = 2;
} // namespace

RealtimePlan setup_realtime(bool want_fifo)
{
	RealtimePlan plan;
	cpu_set_t set;
	CPU_ZERO(&set);
	if (sched_getaffinity(0, sizeof set, &set) == 0) {
		for (int c = CPU_SETSIZE - 1; c >= 0; c--) {
			if (CPU_ISSET(c, &set)) {
				cpu_set_t one;
				CPU_ZERO(&one);
				CPU_SET(c, &one);
				if (sched_setaffinity(0, sizeof one, &one) == 0)
					plan.cpu = c;
				break;
			}
		}
	}
	if (!want_fifo)
		return plan;
	struct sched_param sp = {};
	sp.sched_priority = kCoordinatorPrio;
	if (sched_setscheduler(0, SCHED_FIFO | SCHED_RESET_ON_FORK, &sp) == 0) {
		plan.fifo = true;
		plan.controller_prio = kControllerPrio;
	} else {
		plan.warning = std::string("SCHED_FIFO not permitted (") + std::strerror(errno) +
			       "): preemption is less precise, CPU accounting stays exact. "
			       "Grant CAP_SYS_NICE (root has it) or an rtprio limit of 3 or more (ulimit -r) to fix this.";
	}
	return plan;
}

void coordinator_fifo(const RealtimePlan &plan, bool on)
{
	if (!plan.fifo)
		return;
	struct sched_param sp = {};
	sp.sched_priority = on ? kCoordinatorPrio : 0;
	sched_setscheduler(0, (on ? SCHED_FIFO : SCHED_OTHER) | SCHED_RESET_ON_FORK, &sp);
}

void apply_controller_realtime(const RealtimePlan &plan)
{
	if (!plan.fifo)
		return;
	struct sched_param sp = {};
	sp.sched_priority = plan.controller_prio;
	sched_setscheduler(0, SCHED_FIFO, &sp);
}

} // namespace tcs
