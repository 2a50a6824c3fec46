// Coordinator: the class tcs-run and coordinatord hold. It sets the run
// up (the event loop and what it hears, the lanes, the world, the trace),
// runs it and reports; its state and the parts that work on it are
// run.h's, and who runs next is scheduler.h's.
#include "coordinator.h"

#include <signal.h>
#include <sys/random.h>
#include <sys/signalfd.h>

#include <algorithm>

#include "asleep.h"
#include "children.h"
#include "clock_ns.h"
#include "exits.h"
#include "record_replay.h"
#include "messages.h"
#include "record.h"
#include "remote.h"
#include "run.h"
#include "serve.h"
#include "slices.h"
#include "spin_costs.h"
#include "stop_cost.h"
#include "world_steps.h"
#include "tcs/random_stream.h"

namespace tcs {

namespace {
constexpr int64_t kProgressPeriod = 250 * TCS_NS_PER_MS;
// CLOCK_MONOTONIC and CLOCK_BOOTTIME at virtual time 0 under --epoch
// (docs/DESIGN.md §2): a machine up for a day and a few hours.
constexpr int64_t kFixedMonotonicOrigin = 100000 * TCS_NS_PER_S;
} // namespace

Result<std::unique_ptr<Coordinator>> Coordinator::create(CoordinatorConfig config)
{
	std::unique_ptr<Coordinator> co(new Coordinator());
	co->run_->cfg = std::move(config);
	if (auto s = co->init(); !s)
		return s.error();
	return co;
}

Coordinator::Coordinator() : run_(std::make_unique<Run>())
{
}

// --record and --replay: what each asks of the run's settings.
static Status take_record_settings(Run &run)
{
	CoordinatorConfig &cfg = run.cfg;
	if (!cfg.record_path.empty()) {
		if (cfg.mode != TCS_MODE_CPU)
			return Error{ "--record records a cpu-mode run (a lockstep run repeats by itself with --epoch and --seed)" };
		if (cfg.replay)
			return Error{ "--record and --replay do not go together" };
		if (!cfg.trace_path.empty() && cfg.trace_path != cfg.record_path)
			return Error{ "--record writes its trace itself: no --trace beside it" };
		cfg.trace_path = cfg.record_path;
		// The system's randomness as a stream the record can repeat.
		if (!cfg.seed) {
			uint64_t seed = 0;
			while (seed == 0)
				if (getrandom(&seed, sizeof seed, 0) != (ssize_t)sizeof seed)
					return errno_error("getrandom");
			cfg.seed = seed;
		}
	}
	if (cfg.replay) {
		const Record &r = *cfg.replay;
		if (cfg.mode != TCS_MODE_CPU)
			return Error{ "--replay repeats a cpu-mode run: no --mode beside it" };
		if (r.step_ns != cfg.step_ns)
			return Error{ "the record's world steps every " + std::to_string(r.step_ns) + " ns, this one every " +
				      std::to_string(cfg.step_ns) + " ns: replay it with the record's scenario" };
		cfg.mode = TCS_MODE_LOCKSTEP;
		cfg.seed = r.seed;
		cfg.slack = r.slack;
		run.replaying = true;
	}
	return Ok{};
}

// The event loop and its timers.
static Status init_loop(Run &run)
{
	if (auto s = run.loop.init(); !s)
		return s;
	for (Timer *t : { &run.progress_timer, &run.kill_timer, &run.idle_timer, &run.continue_timer, &run.exit_timer,
			  &run.exec_timer })
		if (auto s = t->init(); !s)
			return s;
	return Ok{};
}

// Signals arrive as events; controllers get a clean mask (spawn.cc).
static Status take_signals(Run &run)
{
	sigset_t mask;
	sigemptyset(&mask);
	for (int s : { SIGINT, SIGTERM, SIGHUP, SIGQUIT })
		sigaddset(&mask, s);
	if (sigprocmask(SIG_BLOCK, &mask, nullptr) < 0)
		return errno_error("sigprocmask");
	run.signal_fd.reset(signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK));
	if (!run.signal_fd)
		return errno_error("signalfd");
	signal(SIGPIPE, SIG_IGN);
	return Ok{};
}

// The cores: the realtime plan, mailbox polling, and the lanes controllers
// run in (with, in cpu mode, what a stop costs on them).
static Status set_up_lanes(Run &run)
{
	run.rt = setup_realtime(run.cfg.realtime);
	if (!run.rt.warning.empty())
		warn_once(run, run.rt.warning);
	// DDS's threads share the coordinator's core: no polling over them.
	run.poller.enable(run.rt.mailbox && !run.cfg.step_host && !run.cfg.step_agent,
		       [&run](Controller &c) { return take_mailbox(run, c); });
	Lanes::Setup lanes;
	lanes.cores = run.rt.cores;
	lanes.coordinator_cpu = run.rt.cpu;
	lanes.mailboxes = run.poller.enabled();
	lanes.lockstep = run.cfg.mode == TCS_MODE_LOCKSTEP;
	if (run.cfg.mode == TCS_MODE_CPU) {
		// Where stops charge what the program never used (cpu mode's
		// charges): measured on the coordinator's core and another.
		lanes.stop_home = measure_stop_cost(run.rt, run.rt.cpu);
		lanes.stop_other = run.rt.cores.size() > 1 ? measure_stop_cost(run.rt, run.rt.cores[1]) : lanes.stop_home;
		run.stop_costs = { lanes.stop_home, lanes.stop_other };
	}
	auto on_budget_of = [&run](Lane &l) { on_budget(run, l); };
	auto on_watchdog_of = [&run](Lane &l) { on_watchdog(run, l); };
	return run.lanes.init(lanes, run.loop, on_budget_of, on_watchdog_of);
}

// The world, if the run has one, and its sensors' noise key: repeated with
// --seed (a key no controller has: theirs are 1, 2, ...), the record's in a
// replay, the machine's randomness otherwise.
static Status make_world(Run &run)
{
	if (run.cfg.models.empty())
		return Ok{};
	auto w = SimWorld::create(run.cfg.models, run.cfg.step_ns);
	if (!w)
		return w.error();
	run.world = std::move(*w);
	uint64_t key = run.cfg.replay ? run.cfg.replay->sensor_key : 0;
	if (key == 0 && run.cfg.seed)
		key = tcs_random_key(*run.cfg.seed, 0);
	if (key == 0 && getrandom(&key, sizeof key, 0) != (ssize_t)sizeof key)
		key = (uint64_t)clock_ns(CLOCK_MONOTONIC);
	run.sensor_key = key ? key : 1;
	return run.world->sense(run.cfg.sensors, run.sensor_key);
}

// The scenario's devices and wires, bound to the world.
static Status bind_devices(Run &run)
{
	auto warn = [&run](const std::string &w) { warn_once(run, w); };
	if (run.cfg.replay)
		run.devices.on_command = [&run](Controller &c, const std::string &path, const std::vector<double> *values) {
			replay_command(run, c, path, values);
		};
	if (auto s = run.devices.bind(run.cfg.devices, run.world.get(), warn); !s)
		return s;
	run.cfg.wires.noise_key = run.sensor_key ? run.sensor_key : 1;
	return run.wires.bind(run.cfg.wires, run.world.get(), warn);
}

// Where the controllers' clocks start: now, or with an epoch fixed values
// (the monotonic clocks too, so that a run repeats their values, not only
// their differences), or the record's.
static Status set_clocks(Run &run)
{
	run.clocks.mono_ns = run.cfg.epoch_ns ? kFixedMonotonicOrigin : clock_ns(CLOCK_MONOTONIC);
	run.clocks.real_ns = run.cfg.epoch_ns ? *run.cfg.epoch_ns : clock_ns(CLOCK_REALTIME);
	// TAI - UTC is a whole number of seconds; two reads differ by a few ns.
	int64_t tai_offset = clock_ns(CLOCK_TAI) - clock_ns(CLOCK_REALTIME);
	tai_offset = (tai_offset + TCS_NS_PER_S / 2) / TCS_NS_PER_S * TCS_NS_PER_S;
	run.clocks.tai_ns = run.clocks.real_ns + tai_offset;
	if (run.cfg.replay) {
		run.clocks.mono_ns = run.cfg.replay->mono_origin_ns;
		run.clocks.real_ns = run.cfg.replay->real_origin_ns;
		run.clocks.tai_ns = run.cfg.replay->tai_origin_ns;
		run.clocks.spin = kNominalSpinCosts; // (not taken: the record says what spins cost)
	}
	return Ok{};
}

// The trace, if asked for, and the joint states each step records there
// (scalar positions and velocities).
static Status open_trace(Run &run)
{
	if (run.cfg.trace_path.empty())
		return Ok{};
	// The coordinator's core is its own where it polls: it writes there.
	TraceWriting how{ .by_caller = run.poller.enabled(), .avoid_cpu = run.rt.cpu };
	if (auto s = run.trace.open(run.cfg.trace_path, how, !run.cfg.record_path.empty(), run.wires.trace_topics(),
				    run.clocks.real_ns);
	    !s)
		return s;
	run.wires.trace_to(run.trace);
	if (how.by_caller)
		run.poller.set_idle_work([&run] { return run.trace.pump(); });
	std::vector<std::string> names;
	for (size_t i = 0; run.world && i < run.world->signal_count(); i++) {
		const tcs_sim_signal_info &sig = run.world->signal(i);
		std::string name = sig.name;
		bool joint = sig.width == 1 && (name.size() > 9 && (name.rfind(".position") == name.size() - 9 ||
								     name.rfind(".velocity") == name.size() - 9));
		if (joint) {
			run.joint_signals.push_back(i);
			names.push_back(name);
		}
	}
	run.trace.set_joint_names(std::move(names));
	return Ok{};
}

// --record: what a replay needs to set the run up again, into the trace.
static Status write_record_settings(Run &run)
{
	if (run.cfg.record_path.empty())
		return Ok{};
	Record r;
	r.cpu_scale = run.cfg.record_scale;
	r.step_ns = run.cfg.step_ns;
	r.mono_origin_ns = run.clocks.mono_ns;
	r.real_origin_ns = run.clocks.real_ns;
	r.tai_origin_ns = run.clocks.tai_ns;
	r.seed = run.cfg.seed;
	r.sensor_key = run.sensor_key;
	r.slack = run.cfg.slack;
	r.duration_ns = run.cfg.duration_ns;
	r.program = run.cfg.record_program;
	r.devices = run.cfg.record_devices;
	run.trace.record_run(record_run_json(r));
	return Ok{};
}

// Lockstep: what a spin's clock read and wait cost, which spinning charges
// (given, nominal with an epoch so that a run repeats, else measured).
static Status take_spin_costs(Run &run)
{
	if (run.cfg.mode == TCS_MODE_LOCKSTEP && !run.cfg.replay)
		run.clocks.spin = run.cfg.spin_costs ? *run.cfg.spin_costs
				  : run.cfg.epoch_ns   ? kNominalSpinCosts
						       : measure_spin_costs();
	return Ok{};
}

// What the event loop hears besides controllers: signals, the step peers,
// the run's timers.
static Status watch_events(Run &run)
{
	// The coordinator shares the running controller's core: each time it
	// wakes, that controller's CPU-time estimates (cpu_estimate.c) are off.
	run.loop.set_on_wake([&run] {
		for (Controller *c : run.lanes.home().running)
			c->coordinator_ran();
	});
	Status st = Ok{};
	auto watch = [&](int fd, EventLoop::Handler h) {
		if (st)
			st = run.loop.add(fd, std::move(h));
	};
	watch(run.signal_fd.get(), [&run](uint32_t) { on_signal(run); });
	if (run.cfg.step_host)
		watch(run.cfg.step_host->fd(), [&run](uint32_t) { on_step_host(run); });
	if (run.cfg.step_agent) {
		watch(run.cfg.step_agent->fd(), [&run](uint32_t) { on_step_agent(run); });
		run.awaiting_grant = true; // no world time until the host's first grant
	}
	watch(run.progress_timer.fd(), [&run](uint32_t) { on_progress(run); });
	watch(run.idle_timer.fd(), [&run](uint32_t) { on_idle(run); });
	watch(run.exec_timer.fd(), [&run](uint32_t) { on_exec_look(run); });
	watch(run.exit_timer.fd(), [&run](uint32_t) {
		run.exit_timer.consume();
		auto again = std::move(run.exiting);
		run.exiting.clear();
		for (Controller *c : again)
			on_pidfd(run, *c);
	});
	watch(run.continue_timer.fd(), [&run](uint32_t) {
		run.continue_timer.consume();
		schedule(run);
	});
	watch(run.kill_timer.fd(), [&run](uint32_t) {
		run.kill_timer.consume();
		for (auto &c : run.ctls)
			if (c->state() != CtlState::Exited)
				kill(c->pid, SIGKILL);
	});
	return st;
}

// A run set up, step by step, in this order: each step uses what those
// before it made (the lanes' cores for the trace's writer, the world for
// the devices, the clocks for the record).
Status Coordinator::init()
{
	Run &run = *run_;
	if (run.cfg.step_ns <= 0)
		return Error{ "the simulation step must be positive" };
	for (Status (*step)(Run &) : { take_record_settings, init_loop, take_signals, set_up_lanes, make_world,
				       bind_devices, set_clocks, open_trace, write_record_settings, take_spin_costs,
				       watch_events })
		if (auto s = step(run); !s)
			return s;
	return Ok{};
}

Coordinator::~Coordinator()
{
	Run &run = *run_;
	// Controller's destructor kills and reaps anything still alive.
	run.ctls.clear();
	// Nothing left to preempt: what follows (the report, the exit, a leak
	// checker's thread on this core) must not wait for RT throttling.
	coordinator_fifo(run.rt, false);
}

Result<RunReport> Coordinator::run()
{
	Run &run = *run_;
	run.wall_start = clock_ns(CLOCK_MONOTONIC);
	// Ticks even without a progress line: the lockstep warning needs it.
	run.progress_timer.arm(kProgressPeriod, kProgressPeriod);
	schedule(run);
	// Served, the run lasts until its end was called and every controller,
	// children too, has gone.
	auto going = [&] { return run.cfg.serve ? !run.ending || alive_controllers(run) > 0 : alive(run) > 0; };
	while (going() && run.fatal) {
		if (auto s = run.poller.turn(run.loop, run.lanes, run.ctls); !s)
			run.fatal = s;
	}
	run.lanes.disarm_budgets();
	run.progress_timer.disarm();
	if (auto s = run.trace.close(); !s && run.fatal)
		run.fatal = Error{ "the trace: " + s.error().message };
	if (!run.fatal)
		return run.fatal.error();

	RunReport r;
	r.reason = run.end_reason;
	r.signal = run.end_signal;
	r.lost = run.lost;
	// Where the world is, or the furthest a controller got when they all
	// exited without waiting for it.
	r.virtual_ns = run.sim_ns;
	if (run.end_reason == EndReason::AllExited)
		for (auto &c : run.ctls)
			r.virtual_ns = std::max(r.virtual_ns, c->v());
	r.wall_ns = clock_ns(CLOCK_MONOTONIC) - run.wall_start;
	r.steps = run.steps;
	r.step_wall_min = run.step_walls.min();
	r.step_wall_median = run.step_walls.median();
	r.step_wall_max = run.step_walls.max();
	r.realtime = run.rt;
	r.stop_costs = run.stop_costs;
	for (auto &c : run.ctls)
		r.controllers.push_back(report_of(run, *c));
	return r;
}

Status Coordinator::add_controller(const ControllerSpec &spec)
{
	return tcs::add_controller(*run_, spec);
}

Result<Coordinator::Attached> Coordinator::attach(const ControllerSpec &spec)
{
	return tcs::attach(*run_, spec);
}

void Coordinator::hold(bool on)
{
	hold_world(*run_, on);
}

void Coordinator::signal_controller(int id, int signo)
{
	tcs::signal_controller(*run_, id, signo);
}

void Coordinator::end_controller(int id)
{
	tcs::end_controller(*run_, id);
}

Status Coordinator::watch(int fd, std::function<void()> on_ready)
{
	return tcs::watch(*run_, fd, std::move(on_ready));
}

void Coordinator::unwatch(int fd)
{
	tcs::unwatch(*run_, fd);
}

int64_t Coordinator::sim_time() const
{
	return run_->sim_ns;
}

int Coordinator::mode() const
{
	return run_->cfg.mode;
}

int Coordinator::fifo_cpu() const
{
	return run_->rt.fifo ? run_->rt.cpu : -1;
}

} // namespace tcs
