// The coordinator: owns virtual time, spawns and schedules controllers with
// SIGSTOP/SIGCONT and CPU budgets, serves their waits, and advances the
// world in fixed steps under conservative synchronisation (docs/DESIGN.md §2).
// tcs-run uses it in-process; it never prints: it reports.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "controller.h"
#include "error.h"
#include "realtime.h"
#include "wires.h"
#include "sim_world.h"
#include "spin_costs.h"
#include "step_peers.h"
#include "stop_cost.h"
#include "tcs/protocol.h"

namespace tcs {

struct ControllerReport;
struct Record;

struct CoordinatorConfig {
	int mode = TCS_MODE_CPU;
	int64_t step_ns = 1000000;          // the simulation step dt
	std::vector<ModelInstance> models;  // the world (none: an empty world)
	std::vector<DeviceConfig> devices;  // its virtual devices
	std::vector<SensorConfig> sensors;  // what its devices' readers see (sensor models)
	WiresConfig wires;                  // its serial lines, I2C buses, CAN interfaces (devices too)
	std::string trace_path;             // write an MCAP trace there (empty: none)
	int64_t duration_ns = -1;           // stop at this virtual time; < 0: when all exit
	std::optional<int64_t> epoch_ns;    // CLOCK_REALTIME at V = 0; default: now
	bool slack = true; // a timed wait ends its thread's timer slack late (--no-slack: exactly)
	// Lockstep: what a spin's clock read and empty read cost (--spin-cost);
	// default: measured, or nominal with an epoch (spin_costs.h).
	std::optional<SpinCosts> spin_costs;
	// --seed: the system's randomness, as programs draw it, a stream fixed
	// by this number (none: real).
	std::optional<uint64_t> seed;
	// --record: a trace there that is also a record (trace/record.h);
	// the run must be cpu mode. The controller's command line, for it.
	std::string record_path;
	std::vector<std::string> record_program;
	double record_scale = 1.0;
	std::vector<std::string> record_devices; // the world's device paths
	// --replay: the record, whose settings (scale, origins, seed, slack)
	// this run takes and whose journals its controllers replay.
	std::shared_ptr<const Record> replay;
	std::string preload;                // absolute path of libtcs_preload.so
	RealtimeWish realtime; // SCHED_FIFO and the TSC, where the machine allows
	// Called about every 250 ms of wall time while running (may be empty).
	std::function<void(int64_t virtual_ns, int64_t wall_ns)> on_progress;
	// Called once per distinct warning (may be empty).
	std::function<void(const std::string &)> on_warning;
	// coordinatord: the run lasts until a signal ends it, controllers come
	// and go (attach()), and a world without any runs at real-time speed.
	bool serve = false;
	// Called when the run's end begins (a signal, the duration).
	std::function<void()> on_ending;
	// A world shared with agents on other hosts (the host's end), or the
	// world of a host elsewhere (an agent's end: the models are then only
	// a mirror its grants fill). At most one; owned by the caller.
	StepHost *step_host = nullptr;
	StepAgent *step_agent = nullptr;
	// Host: the programs an agent runs now (the world may wait for them).
	std::function<void(const std::string &agent, const std::vector<std::string> &programs)> on_agent_controllers;
	// What a daemon logs: agents joining and leaving.
	std::function<void(const std::string &)> on_info;
	// Called when a controller tcs started (not a child of one) has ended.
	std::function<void(const ControllerReport &)> on_controller_end;
	// Called after each step of the world, with the time it has reached
	// (may be empty; it must not block: the run's loop calls it).
	std::function<void(int64_t sim_ns, const SimWorld &world)> on_step;
};

struct ControllerReport {
	int id = 0;
	pid_t pid = -1;
	std::string name;
	int wait_status = -1;     // as from waitpid; -1 if it never ended by itself
	bool ended_by_tcs = false; // stopped by tcs at the end of the run
	bool child = false;        // a child of a controller (its status is not tcs-run's)
	std::string dropped;      // non-empty: tcs dropped it, and why
	bool attached = false;    // libtcs_preload reported in
	int64_t virtual_ns = 0;
	int64_t charged_ns = 0;
	uint64_t waits = 0;           // waits served (including those that returned at once)
	uint64_t spin_stops = 0;      // lockstep: where spins stopped for the world (not waits)
	uint64_t periodic_waits = 0;  // absolute-deadline waits (a periodic loop's cycles)
	uint64_t deadline_misses = 0; // absolute deadlines already past when asked for
	uint64_t preemptions = 0;
};

// A controller attached to a running world (coordinatord).
struct AttachedController {
	int id = 0;
	pid_t pid = -1;
};

// Lost: a peer of the step protocol went silent (RunReport::lost says which).
enum class EndReason { AllExited, Duration, Signal, Lost };

struct RunReport {
	EndReason reason = EndReason::AllExited;
	int signal = 0; // EndReason::Signal
	int64_t virtual_ns = 0;
	int64_t wall_ns = 0;
	int64_t steps = 0;
	// Wall-clock cost of the world's steps (ns; zero for an empty world).
	int64_t step_wall_min = 0, step_wall_median = 0, step_wall_max = 0;
	RealtimePlan realtime;
	StopCosts stop_costs; // left out of cpu mode's charges
	std::vector<ControllerReport> controllers;
	std::string lost; // EndReason::Lost: who, and what it means
};

struct Run;

class Coordinator {
public:
	static Result<std::unique_ptr<Coordinator>> create(CoordinatorConfig config);
	~Coordinator();

	// Spawns a controller (held stopped until run()).
	Status add_controller(const ControllerSpec &spec);
	// Runs until every controller has exited, the duration is reached, or a
	// signal ends the run; every controller is gone when it returns.
	Result<RunReport> run();

	// Serving (coordinatord), from handlers the run's loop calls:
	using Attached = AttachedController;
	// Starts a controller in the running world, at the world's time.
	Result<Attached> attach(const ControllerSpec &spec);
	// While held, nothing runs and the world does not step.
	void hold(bool on);
	// Sends signo to controller id for its caller (Ctrl-C at tcs-run).
	void signal_controller(int id, int signo);
	// Its caller has gone: SIGTERM now, SIGKILL after the end's grace.
	void end_controller(int id);
	// Another fd for the run's loop (a socket, a client).
	Status watch(int fd, std::function<void()> on_ready);
	void unwatch(int fd);
	int64_t sim_time() const;
	int mode() const;
	int fifo_cpu() const;

private:
	Coordinator();
	Status init();

	// Its state, and the parts that work on it: run.h.
	std::unique_ptr<Run> run_;
};

} // namespace tcs
