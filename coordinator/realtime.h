// Precise preemption where the system allows it: the coordinator runs
// SCHED_FIFO above its controllers, pinned to one core, each controller to
// the core it runs on (one of tcs's affinity mask). Where that is
// not permitted, one warning and normal scheduling; CPU accounting stays
// exact either way, only the overshoot of each budget grows.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <sys/types.h>

namespace tcs {

// How a pinned FIFO controller measures the CPU it uses between real
// readings of its CPU-time clock (TCS_PAGE_CPU_ESTIMATE): it uses CPU at the
// rate wall time passes, so any cheap wall clock will do.
enum class EstimateTicks {
	None, // every CPU reading is a system call
	Tsc,  // the TSC: constant rate, running in every C-state, calibrated
	Vdso, // the vDSO's CLOCK_MONOTONIC_RAW (no invariant TSC)
};

struct RealtimePlan {
	bool fifo = false;      // SCHED_FIFO granted
	int controller_prio = 0;
	int cpu = -1;           // the coordinator's core, or -1 (not pinned)
	// The cores controllers may run on (tcs's affinity mask when it
	// started), the coordinator's first; one controller runs on each at a
	// time (coordinator/lanes.cc). Empty: not pinned, one at a time.
	std::vector<int> cores;
	// Controllers on the other cores hand requests over the clock page's
	// mailbox while the coordinator polls (tcs/mailbox.h): FIFO and two
	// cores or more.
	bool mailbox = false;
	std::string warning;    // non-empty: say it once
	EstimateTicks ticks = EstimateTicks::None;
	uint64_t tick_mult = 0;   // ns per tick, times 2^32
	uint64_t tick_resync = 0; // ticks in 20 us
	bool cpu_estimate() const { return ticks != EstimateTicks::None; }
};

// What the machine offers; the test suite can take the TSC away
// (TCS_NO_TSC) to run as on a machine without one.
struct RealtimeWish {
	bool fifo = true;
	bool tsc = true;
	bool mailbox = true;
	// Each preemption's stop this late (sleeping meanwhile: the controller
	// computes on), as on a busy machine where the coordinator gets its
	// core late. For tests only.
	int64_t stop_delay_ns = 0;
	// The nth answer (n > 0) to the first controller's waits is never
	// sent, as a defect of tcs would lose one: the stuck watchdog's test
	// (stuck.cc). For tests only.
	uint64_t lose_wake = 0;
};

// The wish the environment makes: TCS_NO_FIFO, TCS_NO_TSC, TCS_NO_MAILBOX
// (every hand-off through the channel, as on one core), TCS_STOP_DELAY_US
// (1 to 100000; anything else is no delay), TCS_FAULT_LOSE_WAKE (n > 0).
RealtimeWish realtime_wish_from_env();

// Applies the plan to the calling process (the coordinator) before any
// controller is spawned; children inherit the core.
RealtimePlan setup_realtime(RealtimeWish wish);

// While the coordinator computes a heavy world, it steps down to normal
// scheduling: a SCHED_FIFO task using its whole core is held for 50 ms of
// every second by the kernel's real-time throttling. (No controller runs
// meanwhile: the world only steps when every one is stopped or waiting.)
void coordinator_fifo(const RealtimePlan &plan, bool on);

// In a freshly forked controller, before exec: one priority below the
// coordinator. Async-signal-safe.
void apply_controller_realtime(const RealtimePlan &plan);

// The threads of this process (their tids), and moving some to one core
// (their policy stays as it is). A library's threads that hand the
// coordinator its messages (DDS's) wake it fastest from its own core: on
// another, each hand-off is an inter-processor interrupt, several times the
// cost of the hand-off itself on a virtual machine.
std::vector<pid_t> own_threads();
std::vector<pid_t> threads_of(pid_t pid);
void pin_threads(const std::vector<pid_t> &tids, int cpu);

} // namespace tcs
