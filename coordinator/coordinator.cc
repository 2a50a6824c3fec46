// Coordinator: set-up, the run and its end, what the run's loop hears
// besides controllers (signals, progress), and the report. Who runs next
// is scheduler.h's; the parts are in the files coordinator.h names.
#include "coordinator.h"

#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>

#include <algorithm>
#include <cstring>

#include "clock_ns.h"
#include "proc_info.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"

namespace tcs {

namespace {
constexpr int64_t kProgressPeriod = 250 * TCS_NS_PER_MS;
} // namespace

Result<std::unique_ptr<Coordinator>> Coordinator::create(CoordinatorConfig config)
{
	std::unique_ptr<Coordinator> co(new Coordinator());
	co->cfg_ = std::move(config);
	if (auto s = co->init(); !s)
		return s.error();
	return co;
}

Status Coordinator::init()
{
	if (cfg_.step_ns <= 0)
		return Error{ "the simulation step must be positive" };
	if (auto s = loop_.init(); !s)
		return s;
	for (Timer *t : { &progress_timer_, &kill_timer_, &idle_timer_, &continue_timer_, &exit_timer_, &exec_timer_ })
		if (auto s = t->init(); !s)
			return s;

	// Signals arrive as events; controllers get a clean mask (spawn.cc).
	sigset_t mask;
	sigemptyset(&mask);
	for (int s : { SIGINT, SIGTERM, SIGHUP, SIGQUIT })
		sigaddset(&mask, s);
	if (sigprocmask(SIG_BLOCK, &mask, nullptr) < 0)
		return errno_error("sigprocmask");
	signal_fd_.reset(signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK));
	if (!signal_fd_)
		return errno_error("signalfd");
	signal(SIGPIPE, SIG_IGN);

	rt_ = setup_realtime(cfg_.realtime);
	if (!rt_.warning.empty())
		warn_once(rt_.warning);
	// DDS's threads share the coordinator's core: no polling over them.
	poller_.enable(rt_.mailbox && !cfg_.step_host && !cfg_.step_agent,
		       [this](Controller &c) { return take_mailbox(c); });
	Lanes::Setup lanes;
	lanes.cores = rt_.cores;
	lanes.coordinator_cpu = rt_.cpu;
	lanes.mailboxes = poller_.enabled();
	lanes.lockstep = cfg_.mode == TCS_MODE_LOCKSTEP;
	if (auto s = lanes_.init(lanes, loop_, [this](Lane &l) { on_budget(l); }, [this](Lane &l) { on_watchdog(l); }); !s)
		return s;

	if (!cfg_.models.empty()) {
		auto w = SimWorld::create(cfg_.models, cfg_.step_ns);
		if (!w)
			return w.error();
		world_ = std::move(*w);
	}
	if (auto s = devices_.bind(cfg_.devices, world_.get(), [this](const std::string &w) { warn_once(w); }); !s)
		return s;
	if (!cfg_.trace_path.empty()) {
		if (auto s = trace_.open(cfg_.trace_path, rt_.cpu); !s)
			return s;
		// The joint states each step records: scalar positions and velocities.
		std::vector<std::string> names;
		for (size_t i = 0; world_ && i < world_->signal_count(); i++) {
			const tcs_sim_signal_info &sig = world_->signal(i);
			std::string name = sig.name;
			bool joint = sig.width == 1 && (name.size() > 9 && (name.rfind(".position") == name.size() - 9 ||
									     name.rfind(".velocity") == name.size() - 9));
			if (joint) {
				joint_signals_.push_back(i);
				names.push_back(name);
			}
		}
		trace_.set_joint_names(std::move(names));
	}

	origins_.mono_ns = clock_ns(CLOCK_MONOTONIC);
	origins_.real_ns = cfg_.epoch_ns ? *cfg_.epoch_ns : clock_ns(CLOCK_REALTIME);
	// TAI - UTC is a whole number of seconds; two reads differ by a few ns.
	int64_t tai_offset = clock_ns(CLOCK_TAI) - clock_ns(CLOCK_REALTIME);
	tai_offset = (tai_offset + TCS_NS_PER_S / 2) / TCS_NS_PER_S * TCS_NS_PER_S;
	origins_.tai_ns = origins_.real_ns + tai_offset;

	// The coordinator shares the running controller's core: each time it
	// wakes, that controller's CPU-time estimates (cpu_estimate.c) are off.
	loop_.set_on_wake([this] {
		for (Controller *c : lanes_.home().running)
			c->coordinator_ran();
	});
	Status st = Ok{};
	auto watch = [&](int fd, EventLoop::Handler h) {
		if (st)
			st = loop_.add(fd, std::move(h));
	};
	watch(signal_fd_.get(), [this](uint32_t) { on_signal(); });
	if (cfg_.step_host)
		watch(cfg_.step_host->fd(), [this](uint32_t) { on_step_host(); });
	if (cfg_.step_agent) {
		watch(cfg_.step_agent->fd(), [this](uint32_t) { on_step_agent(); });
		awaiting_grant_ = true; // no world time until the host's first grant
	}
	watch(progress_timer_.fd(), [this](uint32_t) { on_progress(); });
	watch(idle_timer_.fd(), [this](uint32_t) { on_idle(); });
	watch(exec_timer_.fd(), [this](uint32_t) { on_exec_look(); });
	watch(exit_timer_.fd(), [this](uint32_t) {
		exit_timer_.consume();
		auto again = std::move(exiting_);
		exiting_.clear();
		for (Controller *c : again)
			on_pidfd(*c);
	});
	watch(continue_timer_.fd(), [this](uint32_t) {
		continue_timer_.consume();
		schedule();
	});
	watch(kill_timer_.fd(), [this](uint32_t) {
		kill_timer_.consume();
		for (auto &c : ctls_)
			if (c->state != CtlState::Exited)
				kill(c->pid, SIGKILL);
	});
	return st;
}

Coordinator::~Coordinator()
{
	// Controller's destructor kills and reaps anything still alive.
	ctls_.clear();
	// Nothing left to preempt: what follows (the report, the exit, a leak
	// checker's thread on this core) must not wait for RT throttling.
	coordinator_fifo(rt_, false);
}

Status Coordinator::add_controller(const ControllerSpec &spec)
{
	ControllerSpec traced = spec;
	traced.report_misses = trace_.is_open();
	auto c = Controller::start((int)ctls_.size() + 1, traced, cfg_.mode, origins_, rt_, cfg_.preload, devices_.bound());
	if (!c)
		return c.error();
	Controller *raw = c->get();
	if (trace_.is_open())
		trace_.controller(raw->id, raw->name, raw->pid, raw->scale, cfg_.mode, cfg_.step_ns);
	ctls_.push_back(std::move(*c));
	if (auto s = loop_.add(raw->channel.get(), [this, raw](uint32_t) { on_channel(*raw, nullptr); }); !s)
		return s;
	return loop_.add(raw->pidfd.get(), [this, raw](uint32_t) { on_pidfd(*raw); });
}

Result<RunReport> Coordinator::run()
{
	wall_start_ = clock_ns(CLOCK_MONOTONIC);
	// Ticks even without a progress line: the lockstep warning needs it.
	progress_timer_.arm(kProgressPeriod, kProgressPeriod);
	schedule();
	// Served, the run lasts until its end was called and every controller,
	// children too, has gone.
	auto going = [&] { return cfg_.serve ? !ending_ || alive_controllers() > 0 : alive() > 0; };
	while (going() && fatal_) {
		if (auto s = poller_.turn(loop_, lanes_, ctls_); !s)
			fatal_ = s;
	}
	lanes_.disarm_budgets();
	progress_timer_.disarm();
	if (auto s = trace_.close(); !s && fatal_)
		fatal_ = Error{ "the trace: " + s.error().message };
	if (!fatal_)
		return fatal_.error();

	RunReport r;
	r.reason = end_reason_;
	r.signal = end_signal_;
	r.lost = lost_;
	// Where the world is, or the furthest a controller got when they all
	// exited without waiting for it.
	r.virtual_ns = sim_ns_;
	if (end_reason_ == EndReason::AllExited)
		for (auto &c : ctls_)
			r.virtual_ns = std::max(r.virtual_ns, c->v);
	r.wall_ns = clock_ns(CLOCK_MONOTONIC) - wall_start_;
	r.steps = steps_;
	r.step_wall_min = step_walls_.min();
	r.step_wall_median = step_walls_.median();
	r.step_wall_max = step_walls_.max();
	r.realtime = rt_;
	for (auto &c : ctls_)
		r.controllers.push_back(report_of(*c));
	return r;
}

ControllerReport Coordinator::report_of(const Controller &c) const
{
	ControllerReport cr;
	cr.id = c.id;
	cr.pid = c.pid;
	cr.name = c.name;
	cr.wait_status = c.exit_status;
	cr.attached = c.attached;
	cr.virtual_ns = c.v;
	cr.charged_ns = c.charged;
	cr.waits = c.stats.waits + c.quick_waits();
	cr.periodic_waits = c.stats.absolute_waits + c.past_deadlines();
	cr.deadline_misses = c.past_deadlines() + c.stats.reported_misses;
	cr.preemptions = c.stats.preemptions;
	cr.ended_by_tcs = c.ended_by_tcs;
	cr.child = c.parent_id != 0;
	cr.dropped = c.dropped;
	return cr;
}

// The run lasts while a controller tcs started lives (children left behind
// are ended with it).
int64_t Coordinator::alive() const
{
	return std::count_if(ctls_.begin(), ctls_.end(),
			     [](auto &c) { return c->parent_id == 0 && c->state != CtlState::Exited; });
}

int64_t Coordinator::alive_controllers() const
{
	return std::count_if(ctls_.begin(), ctls_.end(), [](auto &c) { return c->state != CtlState::Exited; });
}

void Coordinator::on_signal()
{
	struct signalfd_siginfo si;
	while (read(signal_fd_.get(), &si, sizeof si) == (ssize_t)sizeof si) {
		if (ending_ && end_reason_ == EndReason::Signal) {
			// Asked twice: no more grace.
			for (auto &c : ctls_)
				if (c->state != CtlState::Exited)
					kill(c->pid, SIGKILL);
			continue;
		}
		begin_end(EndReason::Signal, (int)si.ssi_signo);
	}
}

void Coordinator::on_progress()
{
	progress_timer_.consume();
	// A parent waits for its new child's registration no longer than this
	// (its program, say, hangs in a constructor before ours runs).
	int64_t now = wall_now();
	for (auto &c : ctls_) {
		if (c->awaiting_child != 0 && now - c->awaiting_since > kRegistrationWait)
			child_settled(*c);
		if (c->kill_after != 0 && now > c->kill_after && c->state != CtlState::Exited)
			kill(c->pid, SIGKILL);
	}
	if (cfg_.step_agent && !granted_ && !ending_)
		word_of_controllers(); // the host may not have heard the last
	if (cfg_.on_progress && !ending_)
		cfg_.on_progress(sim_ns_, clock_ns(CLOCK_MONOTONIC) - wall_start_);
	if (cfg_.mode == TCS_MODE_LOCKSTEP)
		lanes_.each_running([this](Controller &c) {
			if (c.slice_cpu(c.cpu_now()) > 10 * TCS_NS_PER_S)
				warn_once("in lockstep mode virtual time advances only when controllers wait, and '" +
					  c.name + "' has computed for 10 s without waiting");
		});
}

void Coordinator::warn_once(const std::string &what)
{
	if (std::find(warned_.begin(), warned_.end(), what) != warned_.end())
		return;
	warned_.push_back(what);
	if (cfg_.on_warning)
		cfg_.on_warning(what);
}

void Coordinator::begin_end(EndReason reason, int signo)
{
	if (!ending_) {
		end_reason_ = reason;
		end_signal_ = signo;
	} else if (reason == EndReason::Signal && end_reason_ != EndReason::Signal) {
		end_reason_ = reason;
		end_signal_ = signo;
	}
	if (ending_)
		return;
	ending_ = true;
	if (cfg_.on_ending)
		cfg_.on_ending();
	lanes_.each_running([this](Controller &c) {
		// Its slice ends with the run (what it does after is not traced).
		int64_t cpu = c.cpu_now();
		c.account(cpu, cfg_.mode);
		c.publish_slice(cpu);
		trace_slice_end(c, "ended", cpu);
		lanes_.leave(c);
	});
	// Let every controller act on SIGTERM: running, with its waits answered
	// at once, then SIGKILL after the grace period.
	for (auto &c : ctls_) {
		if (c->state == CtlState::Exited)
			continue;
		kill(c->pid, SIGTERM);
		if (c->state == CtlState::Blocked) {
			// It waited through to the end: that is where it stands now.
			c->v = std::max(c->v, std::min(c->wait.deadline, sim_ns_));
			c->wake_pending = true;
			c->wake_reason = TCS_WAKE_DEADLINE;
		}
		if (c->sync_pending)
			complete_sync(*c); // the world has stopped: a read gets its last state
		if (c->wake_pending)
			send_wake(*c);
		end_all_side_waits(*c);
		if (c->stopped) {
			kill(c->pid, SIGCONT);
			c->stopped = false;
		}
		c->state = CtlState::Running;
	}
	kill_timer_.arm(kEndGrace);
}

} // namespace tcs
