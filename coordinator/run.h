// The run's shared state, which every part of the coordinator works on
// (each part's functions take it first, as systemd's take their Manager),
// and what every part asks of the run as a whole: its controllers' count,
// warnings, its end (run.cc). Parts with state of their own own it: the
// lanes, the device server, the agents, the mailbox poller, each
// controller; who runs next is scheduler.h's pure decision.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "agents.h"
#include "controller.h"
#include "coordinator.h"
#include "device_server.h"
#include "duration_stats.h"
#include "error.h"
#include "event_loop.h"
#include "lanes.h"
#include "polling.h"
#include "realtime.h"
#include "scheduler.h"
#include "sim_world.h"
#include "step_peers.h"
#include "tcs/clock_page.h"
#include "tcs/protocol.h"
#include "trace.h"
#include "unique_fd.h"
#include "wires.h"

namespace tcs {

// The shortest slice worth a timer. A timer cycle (interrupt, wake-up,
// CPU-clock read, re-arm) costs a few microseconds of the same core, so a
// shorter slice would leave the controller almost nothing of it: with
// SCHED_FIFO it would never get to run at all. The overshoot this allows
// is carried into the next budget like any other.
constexpr int64_t kMinSlice = 20 * TCS_NS_PER_US;
// The longest a parent waits for its new child to register (wall time).
constexpr int64_t kRegistrationWait = 1 * TCS_NS_PER_S;
// How long controllers get to act on SIGTERM at the end before SIGKILL.
constexpr int64_t kEndGrace = 2 * TCS_NS_PER_S;
// How often a lane's watchdog looks at those running: asleep.cc.
constexpr int64_t kWatchdog = 2 * TCS_NS_PER_MS;
// How far a request's CPU claim may exceed the wall time since its slice
// began: the hook's part before the coordinator ran (charge_point).
constexpr int64_t kClaimSlack = 1 * TCS_NS_PER_MS;

struct Run {
	CoordinatorConfig cfg;
	RealtimePlan rt;
	StopCosts stop_costs;
	ClockSetup clocks;
	EventLoop loop;
	// The coordinator's core's first (its controller's estimates go stale
	// whenever the coordinator runs).
	Lanes lanes;
	MailboxPoller poller;
	Timer progress_timer;
	Timer kill_timer;
	Timer idle_timer;
	// A world running at real-time speed: the wall time its steps are
	// due at (arm_idle_step).
	struct IdlePace {
		int64_t wall = 0, sim = 0; // where it began
		int64_t next_sim = -1; // the step it was armed for
		int64_t wall_for(int64_t at) const { return wall + (at - sim); }
	} idle;
	// Fires at once: a long way for the world to go is computed in slices
	// of wall time, with the event loop (signals, deaths) served between.
	Timer continue_timer;
	// A multi-threaded controller whose main thread has ended reads as
	// ended on its pidfd before its other threads have: looked at again
	// from this timer (not in a loop: on our core, at our priority, they
	// would never get to end).
	Timer exit_timer;
	Timer exec_timer; // a new child's exec, still under way
	std::vector<Controller *> exiting;
	UniqueFd signal_fd;
	std::vector<std::unique_ptr<Controller>> ctls;
	std::unique_ptr<SimWorld> world;
	DeviceServer devices;
	Wires wires;
	DurationStats step_walls; // wall cost of each world step
	Trace trace;
	std::vector<size_t> joint_signals;
	std::vector<double> trace_joints; // a step's joint states for the trace (reused)
	std::vector<std::string> warned;
	std::vector<Contender> contenders; // (kept: schedule() runs on every request)
	bool hearing_threads = false; // hear_threads: schedule() waits for the last

	// --replay: lockstep, with each controller's time from its journal,
	// until one departs from the record (record_replay.cc: then cpu mode).
	bool replaying = false;

	int64_t sim_ns = 0;    // S: the simulation clock
	int64_t steps = 0;
	uint64_t first_wakes = 0; // answers to the first controller's waits (TCS_FAULT_LOSE_WAKE)
	uint64_t sensor_key = 0; // the sensor models' noise stream (SimWorld::sense)
	bool ending = false;
	bool world_held = false; // hold_world: no step until let go
	Agents agents; // host: the agents taking part
	// Agent: answered, and the next grant not here yet (at first: none yet).
	bool awaiting_grant = false;
	bool granted = false;
	std::vector<std::string> programs; // its controllers' programs, as last told
	std::string lost; // a peer gone: why the run ended
	EndReason end_reason = EndReason::AllExited;
	int end_signal = 0;
	int64_t wall_start = 0;
	Status fatal = Ok{};
};

// Spawns a controller (held stopped until the run begins, or, attached,
// from the world's time on) and listens to its channel and its end.
Status add_controller(Run &run, const ControllerSpec &spec);
// c described in the trace (if any): once it starts, again when a child
// execs another program (the trace names it by the program it runs).
void trace_controller(Run &run, const Controller &c);
// The run's end begins (a signal, the duration, a peer lost): every
// controller gets SIGTERM and its waits answered; SIGKILL after kEndGrace.
void begin_end(Run &run, EndReason reason, int signo = 0);
// Controllers tcs started still alive (the run lasts while one is), and
// all alive, children of controllers too.
int64_t alive(const Run &run);
int64_t alive_controllers(const Run &run);
void warn_once(Run &run, const std::string &what);
ControllerReport report_of(const Run &run, const Controller &c);
// What the run's loop hears besides controllers: signals, progress.
void on_signal(Run &run);
void on_progress(Run &run);

} // namespace tcs
