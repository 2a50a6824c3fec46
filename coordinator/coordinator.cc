// Coordinator: set-up, the event handlers, and the end of a run. The
// scheduling decisions themselves are in scheduler.cc.
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
// The longest a parent waits for its new child to register (wall time).
constexpr int64_t kRegistrationWait = 1 * TCS_NS_PER_S;
// How often a child's exec, still under way, is looked at (wall time).
constexpr int64_t kExecLook = 200 * TCS_NS_PER_US;
// Messages a controller may send without an answer (see on_channel).
constexpr int kMaxUnanswered = 4;

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
	mailboxes_ = rt_.mailbox && !cfg_.step_host && !cfg_.step_agent;
	Lanes::Setup lanes;
	lanes.cores = rt_.cores;
	lanes.coordinator_cpu = rt_.cpu;
	lanes.mailboxes = mailboxes_;
	lanes.lockstep = cfg_.mode == TCS_MODE_LOCKSTEP;
	if (auto s = lanes_.init(lanes, loop_, [this](Lane &l) { on_budget(l); }, [this](Lane &l) { on_watchdog(l); }); !s)
		return s;

	if (!cfg_.models.empty()) {
		auto w = SimWorld::create(cfg_.models, cfg_.step_ns);
		if (!w)
			return w.error();
		world_ = std::move(*w);
	}
	if (auto s = bind_devices(); !s)
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
	auto c = Controller::start((int)ctls_.size() + 1, traced, cfg_.mode, origins_, rt_, cfg_.preload, devices_);
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
		if (auto s = turn(); !s)
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

void Coordinator::on_child(Controller &parent, const ::tcs_msg &m, UniqueFd channel)
{
	pid_t pid = (pid_t)m.arg;
	auto refuse = [&](const std::string &why) {
		warn_once("a child of " + parent.name + " runs in real time: " + why);
		if (parent.awaiting_child == pid)
			child_settled(parent);
		if (channel) {
			struct tcs_msg w = tcs_msg_make(TCS_MSG_WAKE, m.seq);
			w.arg = -EPERM;
			(void)send(channel.get(), &w, sizeof w, MSG_DONTWAIT | MSG_NOSIGNAL);
		}
	};
	if (!channel)
		return refuse("it sent no channel");
	// Only a child of this controller may register through its channel.
	if (pid_t pp = proc_parent(pid); pp != parent.pid)
		return refuse("pid " + std::to_string(pid) + " is not its child (its parent is " + std::to_string(pp) +
			      ", not " + std::to_string(parent.pid) + ")");
	for (auto &o : ctls_)
		if (o->pid == pid && o->state != CtlState::Exited)
			return refuse("pid " + std::to_string(pid) + " is registered already");
	ControllerSpec spec;
	spec.cpu_scale = parent.scale;
	spec.report_misses = trace_.is_open();
	auto made = Controller::adopt((int)ctls_.size() + 1, parent, pid, std::move(channel), spec, cfg_.mode, origins_,
				      rt_, devices_);
	if (!made)
		return; // its channel is closed: the child sees it and runs in real time
	Controller &c = **made;
	// It starts where its parent was at the fork (or is now, if it does not
	// know), never behind the world. A parent waiting for this very child
	// (its request restarted its slice) is exactly at parent.v; one still
	// running is settled by that request when it comes (on_forked).
	int64_t parent_v = parent.v;
	if (parent.state == CtlState::Running && cfg_.mode == TCS_MODE_CPU && parent.awaiting_child != pid)
		parent_v = std::max(parent_v, parent.slice().v_base +
						       tcs_scale_cpu(parent.slice_cpu(parent.cpu_now()), parent.scale));
	c.v = std::max((m.flags & TCS_CHILD_V_KNOWN) ? m.v : parent_v, sim_ns_);
	c.wait.seq = m.seq;
	c.state = CtlState::Blocked;
	c.wait.deadline = c.v;
	c.wake_fd = c.page_fd_for_child.release();
	c.wake_arg = 0;
	ctls_.push_back(std::move(*made));
	Controller *raw = ctls_.back().get();
	if (trace_.is_open())
		trace_.controller(raw->id, raw->name, raw->pid, raw->scale, cfg_.mode, cfg_.step_ns);
	if (auto s = loop_.add(raw->channel.get(), [this, raw](uint32_t) { on_channel(*raw, nullptr); }); !s) {
		fatal_ = s;
		return;
	}
	if (auto s = loop_.add(raw->pidfd.get(), [this, raw](uint32_t) { on_pidfd(*raw); }); !s)
		fatal_ = s;
	if (parent.awaiting_child == pid)
		child_settled(parent);
	// Someone new waits for a core: is one that has it asleep?
	lanes_.each_running([this](Controller &r) { arm_watchdog(r); });
}

// The parent, right after its fork: it waits until its child has
// registered (or died first).
void Coordinator::on_forked(Controller &c, const ::tcs_msg &m)
{
	restart_slice(c, m.cpu);
	c.wait.seq = m.seq;
	pid_t pid = (pid_t)m.arg;
	for (auto &o : ctls_)
		if (o->pid == pid && o->parent_id == c.id) {
			// It registered first, while this parent ran on (on a core of
			// its own): at the time of its CPU clock then, which counted
			// the parent's hooks too. Not yet run, it starts here instead,
			// where the spawn's request put its parent.
			if (o->slices == 0 && o->state == CtlState::Blocked && o->wait.deadline == o->v && o->v > c.v)
				o->v = o->wait.deadline = std::max(c.v, sim_ns_);
			reply_now(c, 0);
			return;
		}
	UniqueFd fd((int)syscall(SYS_pidfd_open, pid, 0));
	if (!fd || proc_parent(pid) != c.pid) {
		reply_now(c, -ESRCH);
		return;
	}
	// Started by vfork or posix_spawn, it has exec'd already: a program
	// that will not load the preload never registers (it runs in real
	// time, said once when its parent waits for it).
	WillLoad will = proc_will_load(pid, "libtcs_preload");
	if (will == WillLoad::No) {
		reply_now(c, 0);
		return;
	}
	c.awaiting_child = pid;
	c.awaiting_since = wall_now();
	c.awaiting_exec = will == WillLoad::Unknown;
	if (c.awaiting_exec)
		exec_timer_.arm(kExecLook, kExecLook);
	c.awaiting_child_fd = std::move(fd);
	Controller *raw = &c;
	if (auto s = loop_.add(c.awaiting_child_fd.get(), [this, raw](uint32_t) { child_settled(*raw); }); !s)
		fatal_ = s;
}

// Children whose exec was still under way when their parent asked: looked
// at until they can be seen to load the preload or not.
void Coordinator::on_exec_look()
{
	exec_timer_.consume();
	bool again = false;
	for (auto &c : ctls_) {
		if (c->awaiting_child == 0 || !c->awaiting_exec)
			continue;
		WillLoad will = proc_will_load(c->awaiting_child, "libtcs_preload");
		c->awaiting_exec = will == WillLoad::Unknown;
		if (will == WillLoad::No)
			child_settled(*c);
		again = again || c->awaiting_exec;
	}
	if (!again)
		exec_timer_.disarm();
}

void Coordinator::child_settled(Controller &parent)
{
	if (parent.awaiting_child == 0)
		return;
	loop_.remove(parent.awaiting_child_fd.get());
	parent.awaiting_child_fd.reset();
	parent.awaiting_child = 0;
	if (parent.state != CtlState::Exited)
		reply_now(parent, 0);
}

// One message per call: the loop is level-triggered, so a channel with more
// comes back after the others had their turn. Drained in a loop, a channel
// whose thread always had its next request there by the time the last was
// answered (the coordinator paused in a system call, under load) kept the
// coordinator from ever going back to epoll, and another thread's wait went
// unread for hundreds of virtual ms.
void Coordinator::on_channel(Controller &c, ThreadChannel *t)
{
	const int fd = t ? t->fd.get() : c.channel.get();
	ChannelState &st = t ? t->state : c.main_state;
	alignas(8) unsigned char buf[sizeof(struct tcs_msg) + 1];
	// A child or a thread registering passes its channel (SCM_RIGHTS); an
	// fd that comes with any other message is closed.
	struct tcs_msg_io io;
	tcs_msg_io_recv(&io, buf, sizeof buf);
	ssize_t n = recvmsg(fd, &io.mh, MSG_DONTWAIT | MSG_CMSG_CLOEXEC);
	if (n < 0 && (errno == EAGAIN || errno == EINTR))
		return;
	UniqueFd passed(n > 0 ? tcs_msg_io_fd(&io) : -1);
	if (n == 0 || (n < 0 && errno == ECONNRESET)) {
		take_lazy_commands(c, -1);
		// Every copy of this end is closed: the thread has ended, or the
		// controller is exiting (its pidfd tells when).
		if (t)
			thread_gone(c, t);
		else
			loop_.remove(c.channel.get());
		return;
	}
	struct tcs_msg m;
	if (const char *why = tcs_msg_check(buf, (long)n, &m)) {
		take_lazy_commands(c, -1);
		drop(c, std::string("bad message on its channel: ") + why);
		return;
	}
	// What it posted in its mailbox came before anything that followed on
	// the channel (an EARLY from its parked wait, say).
	const bool took = !t && take_mailbox(c);
	if (!c.dropped.empty())
		return;
	if (m.type == TCS_MSG_DOORBELL) {
		// Rung for a request already taken while polling, or now.
		if (t)
			drop(c, "a DOORBELL on a thread's channel");
		else if (!took && ++st.unanswered > kMaxUnanswered)
			drop(c, "it rings without a request in its mailbox");
		return;
	}
	on_request(c, t, m, std::move(passed));
}

void Coordinator::on_request(Controller &c, ThreadChannel *t, const ::tcs_msg &m, UniqueFd passed)
{
	const int fd = t ? t->fd.get() : c.channel.get();
	const pid_t tid = t ? t->tid : c.pid;
	ChannelState &st = t ? t->state : c.main_state;
	// Records it wrote since its last request carry the time it has now,
	// before anything it asks moves that. (A device it asks to take what
	// it wrote: that request takes them, and judges them with its write.)
	take_lazy_commands(c, m.type == TCS_MSG_DEV_SYNC && m.kind == TCS_SYNC_WRITE ? m.arg : -1);
	if (!t && m.type == TCS_MSG_CHILD && !(m.flags & TCS_CHILD_PARENT)) {
		// From a new child, not from c: it waits on its own channel.
		on_child(c, m, std::move(passed));
		return;
	}
	if (!t && m.type == TCS_MSG_THREAD) {
		on_thread(c, m, std::move(passed));
		return;
	}
	// The preload waits for the answer to each request: its HELLO, one
	// request and the EARLY that may cross the answer (and one from another
	// thread ending its wait) are all it can have outstanding. More is a
	// flood.
	if (++st.unanswered > kMaxUnanswered) {
		drop(c, "it floods its channel (" + std::to_string(st.unanswered) + " messages without waiting for an answer)");
		return;
	}
	on_message(c, m, fd, tid);
}

void Coordinator::on_message(Controller &c, const ::tcs_msg &m, int fd, pid_t tid)
{
	if (c.asleep)
		wake_from_asleep(c); // it woke by itself and asks something
	if (m.type != TCS_MSG_BLOCK && m.type != TCS_MSG_EARLY)
		c.wait.fd = fd; // a request answered at once, on its thread's channel
	switch (m.type) {
	case TCS_MSG_HELLO:
		if (fd != c.channel.get()) {
			drop(c, "HELLO on a thread's channel");
			return;
		}
		if (m.arg != c.pid) {
			drop(c, "HELLO from pid " + std::to_string(m.arg) + " on pid " + std::to_string(c.pid) + "'s channel");
			return;
		}
		// Again after an exec (a new image, a new nonce): welcome.
		if (c.attached && m.v == c.hello_nonce) {
			drop(c, "it said HELLO twice");
			return;
		}
		c.attached = true;
		c.hello_nonce = m.v;
		if (c.parent_id != 0)
			c.name = proc_name(c.pid, c.name); // a child after its exec
		c.main_state = ChannelState{}; // a new image owes nothing yet
		return;
	case TCS_MSG_BLOCK:
		on_block(c, m, fd, tid);
		return;
	case TCS_MSG_EARLY:
		on_early(c, m, fd);
		return;
	case TCS_MSG_DEV_OPEN:
		on_dev_open(c, m);
		return;
	case TCS_MSG_DEV_SYNC:
		on_dev_sync(c, m);
		return;
	case TCS_MSG_TIMER:
		on_timer(c, m);
		return;
	case TCS_MSG_CHILD:
		on_forked(c, m);
		return;
	case TCS_MSG_THREAD:
		drop(c, "THREAD on a thread's channel");
		return;
	case TCS_MSG_KILL:
		on_kill(c, m);
		return;
	}
}

// The CPU clock of a controller that has just ended. The kernel's sum over
// its threads waits for a thread still on its way out, which our wake-up
// may have preempted on our core: at SCHED_FIFO we would spin in that
// clock_gettime forever (seen with every multi-threaded controller), so we
// step down to let it finish.
int64_t Coordinator::exited_cpu(const Controller &c)
{
	coordinator_fifo(rt_, false);
	int64_t cpu = c.cpu_now();
	coordinator_fifo(rt_, true);
	return cpu;
}

void Coordinator::on_pidfd(Controller &c)
{
	if (c.state == CtlState::Exited)
		return;
	if (c.parent_id != 0) {
		// A child of a controller: its parent reaps it, not us. Its pidfd
		// being readable says it has ended; its zombie (if the parent has
		// not reaped it yet) still tells its CPU and exit status.
		int64_t cpu = exited_cpu(c);
		if (cpu > 0)
			c.account(cpu, cfg_.mode);
		if (c.lane >= 0)
			trace_slice_end(c, "exited", std::max<int64_t>(cpu, 0));
		on_exit(c, proc_exit_status(c.pid));
		return;
	}
	siginfo_t si = {};
	// Peek first: a zombie's CPU clock still reads, so its last slice counts.
	if (waitid(P_PIDFD, (id_t)c.pidfd.get(), &si, WEXITED | WNOHANG | WNOWAIT) < 0)
		return;
	// Its main thread has ended, not yet all of it: look again soon.
	auto later = [&] {
		loop_.remove(c.pidfd.get());
		if (std::find(exiting_.begin(), exiting_.end(), &c) == exiting_.end())
			exiting_.push_back(&c);
		exit_timer_.arm(100 * TCS_NS_PER_US);
	};
	if (si.si_pid == 0)
		return later();
	int64_t cpu = exited_cpu(c);
	c.account(cpu, cfg_.mode);
	if (c.lane >= 0)
		trace_slice_end(c, "exited", cpu);
	si = {};
	if (waitid(P_PIDFD, (id_t)c.pidfd.get(), &si, WEXITED | WNOHANG) < 0)
		return;
	if (si.si_pid == 0)
		return later();
	int status = si.si_code == CLD_EXITED ? W_EXITCODE(si.si_status, 0) : si.si_status & 0x7f;
	if (si.si_code == CLD_DUMPED)
		status |= WCOREFLAG;
	on_exit(c, status);
}

void Coordinator::on_exit(Controller &c, int wait_status)
{
	take_lazy_commands(c, -1); // its last commands count
	c.state = CtlState::Exited;
	c.exit_status = wait_status;
	// A parent waiting for its children learns of it at the child's
	// virtual time; one waiting for something else was sent SIGCHLD then
	// (a handler of it may end its wait, as in coreutils timeout).
	for (auto &p : ctls_) {
		if (p->id != c.parent_id)
			continue;
		bool seen = false;
		for (SideWait &w : p->side)
			if (w.flags & TCS_BLOCK_CHILD) {
				w.wake_reason = TCS_WAKE_RECHECK;
				seen = true;
			}
		if (p->state == CtlState::Blocked && p->wait.for_child && !p->sync_pending) {
			wake(*p, std::max(p->v, c.v), TCS_WAKE_RECHECK);
			seen = true;
		} else if (p->state == CtlState::Blocked) {
			kick(*p, std::max(p->v, c.v));
		}
		// Not waiting for it now: its next wait for a child re-checks.
		p->child_ended = !seen;
	}
	loop_.remove(c.channel.get());
	for (auto &t : c.threads)
		loop_.remove(t->fd.get());
	c.threads.clear();
	c.side.clear();
	loop_.remove(c.pidfd.get());
	lanes_.leave(c);
	c.ended_by_tcs = ending_;
	if (c.parent_id == 0 && cfg_.serve) {
		// Served: its children go with it, as they do at the end of a run.
		for (auto &o : ctls_)
			if (o->state != CtlState::Exited && descends_from(*o, c.id))
				kill(o->pid, SIGKILL);
		if (cfg_.on_controller_end)
			cfg_.on_controller_end(report_of(c));
		word_of_controllers();
	}
	if (cfg_.serve)
		c.release(); // served for long: its fds and memory go back now
	schedule();
}

void Coordinator::drop(Controller &c, const std::string &why)
{
	c.dropped = why;
	c.mailbox.attach(nullptr); // nothing more of it is looked at
	kill(c.pid, SIGKILL);
	// Its pidfd reports the death; until then it must not be scheduled.
	lanes_.leave(c);
	loop_.remove(c.channel.get());
	for (auto &t : c.threads)
		loop_.remove(t->fd.get());
	c.threads.clear();
	c.side.clear();
	c.state = CtlState::Blocked;
	c.wait.deadline = TCS_NEVER;
	c.wait.recheck = false;
	c.wait.devices = false;
	c.sync_pending = false;
	c.wake_pending = false;
	schedule();
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
