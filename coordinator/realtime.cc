// setup_realtime(): SCHED_FIFO and core pinning, with a clear fallback.
#include "realtime.h"
#include "clock_ns.h"
#include "tcs/protocol.h"

#include <dirent.h>
#include <sched.h>
#include <time.h>
#if defined(__x86_64__)
#include <x86intrin.h>
#endif

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace tcs {

namespace {
// Low real-time priorities: above every normal task, below the kernel's
// own threaded interrupt handlers (50), which must keep running.
constexpr int kCoordinatorPrio = TCS_CONTROLLER_FIFO_PRIO + 1;
constexpr int kControllerPrio = TCS_CONTROLLER_FIFO_PRIO;

int64_t mono_raw_ns()
{
	return clock_ns(CLOCK_MONOTONIC_RAW);
}

// The CPU's own word on its TSC (x86 /proc/cpuinfo flags): a constant rate
// whatever the frequency, and running in every C-state. Not the kernel's
// clocksource: a VM's kernel may keep time with kvm-clock and mark the TSC
// unstable across its vCPUs, yet on one pinned core it counts true.
bool cpu_has_invariant_tsc()
{
	std::ifstream info("/proc/cpuinfo");
	std::string line;
	while (std::getline(info, line)) {
		if (line.rfind("flags", 0) != 0)
			continue;
		line += ' ';
		return line.find(" constant_tsc ") != std::string::npos && line.find(" nonstop_tsc ") != std::string::npos;
	}
	return false;
}

#if defined(__x86_64__)
// A TSC reading and CLOCK_MONOTONIC_RAW at the same moment: the tightest of
// a few pairs, since a pause (an interrupt, the VM descheduled) between the
// reads would skew a rate measured from them.
struct TscPair {
	uint64_t tsc = 0;
	int64_t ns = 0;
};

TscPair tsc_pair()
{
	TscPair p;
	uint64_t best = UINT64_MAX;
	for (int i = 0; i < 5; i++) {
		uint64_t a = __rdtsc();
		int64_t ns = mono_raw_ns();
		uint64_t b = __rdtsc();
		if (b - a < best) {
			best = b - a;
			p = { a + (b - a) / 2, ns };
		}
	}
	return p;
}

double tsc_per_ns(const TscPair &a, const TscPair &b)
{
	return b.tsc > a.tsc && b.ns > a.ns ? (double)(b.tsc - a.tsc) / (double)(b.ns - a.ns) : 0.0;
}

void pause_ms(int64_t ms)
{
	struct timespec wait = { 0, ms * 1000000 };
	while (nanosleep(&wait, &wait) != 0 && errno == EINTR) {
	}
}

// The TSC's rate against CLOCK_MONOTONIC_RAW, from three pairs 1 ms apart:
// the two rates must agree to 0.1 % (a TSC that stops, jumps or is not the
// rate it seems fails that), or, twice more, the TSC is not used.
bool calibrate_tsc(RealtimePlan &plan)
{
	for (int attempt = 0; attempt < 3; attempt++) {
		TscPair p0 = tsc_pair();
		pause_ms(1);
		TscPair p1 = tsc_pair();
		pause_ms(1);
		TscPair p2 = tsc_pair();
		double r1 = tsc_per_ns(p0, p1), r2 = tsc_per_ns(p1, p2);
		if (r1 <= 0 || r2 <= 0 || std::fabs(r1 - r2) > 0.001 * r2)
			continue;
		double rate = tsc_per_ns(p0, p2);
		plan.ticks = EstimateTicks::Tsc;
		plan.tick_mult = (uint64_t)(4294967296.0 / rate);
		plan.tick_resync = (uint64_t)(rate * 20000.0);
		return plan.tick_mult > 0 && plan.tick_resync > 0;
	}
	return false;
}
#endif

// Whether CLOCK_MONOTONIC_RAW is read without entering the kernel (the
// vDSO): a few times cheaper than the cheapest system call. Where the
// clocksource offers no vDSO read, it is a system call itself, and an
// estimate from it would save nothing.
bool mono_raw_is_vdso()
{
	auto cost = [](auto &&fn) {
		int64_t best = INT64_MAX;
		for (int round = 0; round < 5; round++) {
			int64_t t0 = mono_raw_ns();
			for (int i = 0; i < 100; i++)
				fn();
			best = std::min(best, mono_raw_ns() - t0);
		}
		return best;
	};
	int64_t vdso = cost([] { (void)mono_raw_ns(); });
	int64_t syscall = cost([] { (void)getppid(); });
	return 3 * vdso < syscall;
}

// How a pinned FIFO controller will estimate its CPU (see EstimateTicks);
// a reason for the warning when it must take a slower way.
std::string choose_ticks(RealtimePlan &plan, bool want_tsc)
{
	bool invariant = cpu_has_invariant_tsc();
#if defined(__x86_64__)
	if (want_tsc && invariant && calibrate_tsc(plan))
		return "";
#else
	// The preload's estimate is x86-64's (libtcs_preload/cpu_estimate.c).
	(void)invariant;
	return "not an x86-64 machine: every cpu-mode clock read is a system call";
#endif
	std::string why = !want_tsc ? "the TSC is not to be used (TCS_NO_TSC)"
			  : invariant ? "the TSC's rate did not hold steady against CLOCK_MONOTONIC_RAW"
				      : "the CPU reports no invariant TSC (constant_tsc and nonstop_tsc)";
	if (mono_raw_is_vdso()) {
		plan.ticks = EstimateTicks::Vdso;
		plan.tick_mult = 1ull << 32;
		plan.tick_resync = 20000;
		return why + ": cpu-mode clock reads estimate the CPU from the vDSO clock, slower than from the TSC";
	}
	return why + ", and CLOCK_MONOTONIC_RAW is a system call here: every cpu-mode clock read is a system call";
}

} // namespace

RealtimeWish realtime_wish_from_env()
{
	RealtimeWish w;
	w.fifo = getenv("TCS_NO_FIFO") == nullptr;
	w.tsc = getenv("TCS_NO_TSC") == nullptr;
	w.mailbox = getenv("TCS_NO_MAILBOX") == nullptr;
	if (const char *s = getenv("TCS_STOP_DELAY_US")) {
		char *end;
		long us = strtol(s, &end, 10);
		if (*s && !*end && us > 0 && us <= 100000)
			w.stop_delay_ns = us * 1000;
	}
	if (const char *s = getenv("TCS_FAULT_LOSE_WAKE")) {
		char *end;
		unsigned long long n = strtoull(s, &end, 10);
		if (*s && !*end)
			w.lose_wake = n;
	}
	return w;
}

RealtimePlan setup_realtime(RealtimeWish wish)
{
	RealtimePlan plan;
	cpu_set_t set;
	CPU_ZERO(&set);
	if (sched_getaffinity(0, sizeof set, &set) == 0) {
		for (int c = CPU_SETSIZE - 1; c >= 0; c--) {
			if (!CPU_ISSET(c, &set))
				continue;
			if (plan.cpu < 0) {
				cpu_set_t one;
				CPU_ZERO(&one);
				CPU_SET(c, &one);
				if (sched_setaffinity(0, sizeof one, &one) != 0)
					break;
				plan.cpu = c;
			}
			plan.cores.push_back(c);
		}
	}
	if (!wish.fifo)
		return plan;
	struct sched_param sp = {};
	sp.sched_priority = kCoordinatorPrio;
	if (sched_setscheduler(0, SCHED_FIFO | SCHED_RESET_ON_FORK, &sp) == 0) {
		plan.fifo = true;
		plan.controller_prio = kControllerPrio;
		plan.mailbox = wish.mailbox && plan.cores.size() >= 2;
		if (plan.cpu >= 0)
			plan.warning = choose_ticks(plan, wish.tsc);
	} else {
		plan.warning = std::string("SCHED_FIFO not permitted (") + std::strerror(errno) +
			       "): preemption is less precise and every cpu-mode clock read is a system call; "
			       "CPU accounting stays exact. "
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

std::vector<pid_t> threads_of(pid_t pid)
{
	std::vector<pid_t> tids;
	std::string dir = "/proc/" + std::to_string(pid) + "/task";
	if (DIR *d = opendir(dir.c_str())) {
		while (struct dirent *e = readdir(d))
			if (e->d_name[0] != '.')
				tids.push_back((pid_t)atoi(e->d_name));
		closedir(d);
	}
	return tids;
}

std::vector<pid_t> own_threads()
{
	return threads_of(getpid());
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
