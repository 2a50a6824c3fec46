// setup_realtime(): SCHED_FIFO and core pinning, with a clear fallback.
#include "realtime.h"
#include "tcs/protocol.h"

#include <dirent.h>
#include <sched.h>
#include <time.h>
#if defined(__x86_64__)
#include <x86intrin.h>
#endif

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace tcs {

namespace {
// Low real-time priorities: above every normal task, below the kernel's
// own threaded interrupt handlers (50), which must keep running.
constexpr int kCoordinatorPrio = TCS_CONTROLLER_FIFO_PRIO + 1;
constexpr int kControllerPrio = TCS_CONTROLLER_FIFO_PRIO;

// The TSC rate against CLOCK_MONOTONIC_RAW over 2 ms, where the CPU says
// its TSC is invariant (constant rate, running in every C-state) and the
// kernel keeps time with it.
void calibrate_tsc(RealtimePlan &plan)
{
#if defined(__x86_64__)
	std::ifstream info("/proc/cpuinfo");
	std::string line;
	bool constant = false, nonstop = false;
	while (std::getline(info, line) && !(constant && nonstop)) {
		if (line.rfind("flags", 0) != 0)
			continue;
		constant = line.find(" constant_tsc") != std::string::npos;
		nonstop = line.find(" nonstop_tsc") != std::string::npos;
	}
	std::ifstream source("/sys/devices/system/clocksource/clocksource0/current_clocksource");
	std::string clocksource;
	source >> clocksource;
	if (!constant || !nonstop || clocksource != "tsc")
		return;
	// The tightest of a few pairs: a pause (an interrupt, the VM descheduled)
	// between the TSC reads and the clock read would skew the rate by as
	// much over the 2 ms.
	auto sample = [](uint64_t &tsc, int64_t &ns) {
		uint64_t best = UINT64_MAX;
		for (int i = 0; i < 5; i++) {
			struct timespec ts;
			uint64_t a = __rdtsc();
			clock_gettime(CLOCK_MONOTONIC_RAW, &ts);
			uint64_t b = __rdtsc();
			if (b - a < best) {
				best = b - a;
				tsc = a + (b - a) / 2;
				ns = (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
			}
		}
	};
	uint64_t t0, t1;
	int64_t n0, n1;
	sample(t0, n0);
	struct timespec wait = { 0, 2000000 };
	while (nanosleep(&wait, &wait) != 0 && errno == EINTR) {
	}
	sample(t1, n1);
	if (t1 <= t0 || n1 <= n0)
		return;
	plan.tsc_mult = (uint64_t)(((unsigned __int128)(n1 - n0) << 32) / (t1 - t0));
	plan.tsc_resync = (uint64_t)((double)(t1 - t0) / (double)(n1 - n0) * 20000.0);
	plan.cpu_estimate = plan.tsc_mult > 0 && plan.tsc_resync > 0;
#else
	(void)plan;
#endif
}

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
		if (plan.cpu >= 0)
			calibrate_tsc(plan);
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

std::vector<pid_t> own_threads()
{
	std::vector<pid_t> tids;
	if (DIR *d = opendir("/proc/self/task")) {
		while (struct dirent *e = readdir(d))
			if (e->d_name[0] != '.')
				tids.push_back((pid_t)atoi(e->d_name));
		closedir(d);
	}
	return tids;
}

void pin_threads(const std::vector<pid_t> &tids, int cpu)
{
	if (cpu < 0)
		return;
	cpu_set_t set;
	CPU_ZERO(&set);
	CPU_SET(cpu, &set);
	for (pid_t t : tids)
		sched_setaffinity(t, sizeof set, &set);
}

} // namespace tcs
