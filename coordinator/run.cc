// What every part asks of the run as a whole (run.h): a new controller,
// the count of the living, warnings, the end and the report, and what the
// run's loop hears besides controllers (signals, progress).
#include "run.h"

#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>

#include <algorithm>
#include <cstring>

#include "asleep.h"
#include "children.h"
#include "clock_ns.h"
#include "device_requests.h"
#include "exits.h"
#include "messages.h"
#include "proc_info.h"
#include "record.h"
#include "remote.h"
#include "serve.h"
#include "slices.h"
#include "stuck.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"
#include "tcs/random_stream.h"
#include "threads.h"
#include "waits.h"
#include "world_steps.h"
#include "transitions.h"

namespace tcs {

Status add_controller(Run &run, const ControllerSpec &spec)
{
	ControllerSpec traced = spec;
	// (A replay waits as its record did, which was traced.)
	traced.report_misses = run.trace.is_open() || run.cfg.replay;
	// Each controller a stream of its own, by its place in the run.
	if (run.cfg.seed)
		traced.random_key = tcs_random_key(*run.cfg.seed, run.ctls.size() + 1);
	const int id = (int)run.ctls.size() + 1;
	traced.record = !run.cfg.record_path.empty();
	if (run.cfg.replay) {
		auto scale = run.cfg.replay->scales.find(id);
		traced.cpu_scale = scale != run.cfg.replay->scales.end() ? scale->second : run.cfg.replay->cpu_scale;
		auto j = run.cfg.replay->journals.find(id);
		static const std::vector<tcs_journal_entry> none;
		traced.replay = j != run.cfg.replay->journals.end() ? &j->second : &none;
	}
	auto c = Controller::start(id, traced, run.cfg.mode, run.clocks, run.rt, run.cfg.preload,
				   run.devices.bound());
	if (!c)
		return c.error();
	Controller *raw = c->get();
	trace_controller(run, *raw);
	run.ctls.push_back(std::move(*c));
	if (auto s = run.loop.add(raw->channel.get(), [&run, raw](uint32_t) { on_channel(run, *raw, nullptr); }); !s)
		return s;
	return run.loop.add(raw->pidfd.get(), [&run, raw](uint32_t) { on_pidfd(run, *raw); });
}

ControllerReport report_of(const Run &run, const Controller &c)
{
	ControllerReport cr;
	cr.id = c.id;
	cr.pid = c.pid;
	cr.name = c.name;
	cr.wait_status = c.exit_status;
	cr.attached = c.attached;
	cr.virtual_ns = c.v();
	cr.charged_ns = c.charged;
	cr.waits = c.stats.waits + c.quick_waits();
	cr.spin_stops = c.stats.spin_stops;
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
int64_t alive(const Run &run)
{
	return std::count_if(run.ctls.begin(), run.ctls.end(),
			     [](auto &c) { return c->parent_id == 0 && c->state() != CtlState::Exited; });
}

int64_t alive_controllers(const Run &run)
{
	return std::count_if(run.ctls.begin(), run.ctls.end(), [](auto &c) { return c->state() != CtlState::Exited; });
}

void trace_controller(Run &run, const Controller &c)
{
	if (run.trace.is_open())
		run.trace.controller(c.id, c.name, c.pid, c.scale, run.cfg.replay ? TCS_MODE_CPU : run.cfg.mode,
				     run.cfg.step_ns);
}

void on_signal(Run &run)
{
	struct signalfd_siginfo si;
	while (read(run.signal_fd.get(), &si, sizeof si) == (ssize_t)sizeof si) {
		if (run.ending && run.end_reason == EndReason::Signal) {
			// Asked twice: no more grace.
			for (auto &c : run.ctls)
				if (c->state() != CtlState::Exited)
					kill(c->pid, SIGKILL);
			continue;
		}
		begin_end(run, EndReason::Signal, (int)si.ssi_signo);
	}
}

void on_progress(Run &run)
{
	run.progress_timer.consume();
	// A parent waits for its new child's registration no longer than this
	// (its program, say, hangs in a constructor before ours runs).
	int64_t now = wall_now();
	for (auto &c : run.ctls) {
		if (c->new_child.pid != 0 && now - c->new_child.since > kRegistrationWait)
			child_settled(run, *c);
		if (c->kill_after != 0 && now > c->kill_after && c->state() != CtlState::Exited)
			kill(c->pid, SIGKILL);
	}
	look_for_stuck(run);
	if (run.cfg.step_agent && !run.granted && !run.ending)
		word_of_controllers(run); // the host may not have heard the last
	if (run.cfg.on_progress && !run.ending)
		run.cfg.on_progress(run.sim_ns, clock_ns(CLOCK_MONOTONIC) - run.wall_start);
	if (run.cfg.mode == TCS_MODE_LOCKSTEP)
		run.lanes.each_running([&run](Controller &c) {
			if (c.slice_cpu(c.cpu_now()) > 10 * TCS_NS_PER_S)
				warn_once(run, "in lockstep mode virtual time advances only when controllers wait, and '" +
					  c.name + "' has computed for 10 s without waiting");
		});
}

void warn_once(Run &run, const std::string &what)
{
	if (std::find(run.warned.begin(), run.warned.end(), what) != run.warned.end())
		return;
	run.warned.push_back(what);
	if (run.cfg.on_warning)
		run.cfg.on_warning(what);
}

void begin_end(Run &run, EndReason reason, int signo)
{
	if (!run.ending) {
		run.end_reason = reason;
		run.end_signal = signo;
	} else if (reason == EndReason::Signal && run.end_reason != EndReason::Signal) {
		run.end_reason = reason;
		run.end_signal = signo;
	}
	if (run.ending)
		return;
	run.ending = true;
	if (run.cfg.on_ending)
		run.cfg.on_ending();
	run.lanes.each_running([&run](Controller &c) {
		// Its slice ends with the run (what it does after is not traced).
		int64_t cpu = c.cpu_now();
		c.account(cpu, run.cfg.mode);
		c.publish_slice(cpu);
		trace_slice_end(run, c, "ended", cpu);
		run.lanes.leave(c);
	});
	// Let every controller act on SIGTERM: running, with its waits answered
	// at once, then SIGKILL after the grace period. One that SIGTERM simply
	// ends is not woken: it would run on, until the signal landed, past a
	// wait the run did not end (a read "timed out", a loop's extra cycle).
	for (auto &c : run.ctls) {
		if (c->state() == CtlState::Exited || c->state() == CtlState::Dropped)
			continue; // (a dropped one is being killed)
		const bool dies = proc_signal_kills(c->pid, SIGTERM);
		kill(c->pid, SIGTERM);
		if (waiting(c->state())) {
			// It waited through to the end: that is where it stands now,
			// and where its clocks go on from (its page still held the
			// slice before its wait: a program's last reads went back).
			advance(*c, std::min(c->wait.deadline, run.sim_ns));
			owe_answer(*c, TCS_WAKE_DEADLINE, c->wait.result);
			c->publish_slice(c->cpu_at_end >= 0 ? c->cpu_at_end : c->cpu_now());
			c->cpu_at_end = -1;
		}
		if (!dies) {
			if (c->sync)
				complete_sync(run, *c); // the world has stopped: a read gets its last state
			if (c->wait.owed)
				send_wake(run, *c);
			end_all_side_waits(run, *c);
		}
		if (c->stopped)
			let_go(run, *c);
		move(run, *c, CtlMove::End);
	}
	run.kill_timer.arm(kEndGrace);
}

} // namespace tcs
