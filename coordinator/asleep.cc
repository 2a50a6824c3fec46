// Controllers asleep in the kernel outside tcs's hooks: a parent reading a
// pipe its child writes, a waitpid inside libc, a futex only another
// process wakes. While one holds the core as "running", no one else would
// ever run. When others live, the running controller is looked at — by its
// budget's own checks, or by a watchdog when it has no budget (lockstep):
// if it used no CPU since the last look and every thread of it sleeps, it
// steps aside (others go on meanwhile), and it is looked at again at each
// step, resuming once it is runnable, at the world's time then. A lane's
// watchdog looks at each controller queued in it (lanes.cc). The
// watchdog is slow (every 2 ms) because each look interrupts the controller
// on its core.
#include "asleep.h"

#include "proc_info.h"
#include "slices.h"
#include "threads.h"
#include "world_steps.h"
#include "transitions.h"

namespace tcs {

void arm_watchdog(Run &run, Controller &c)
{
	// Only worth it when someone else may be waiting for the core, or
	// when its threads may all be waiting.
	Lane *lane = run.lanes.of(c);
	if (!lane || (alive_controllers(run) < 2 && c.side_waits.empty()))
		return;
	// A lane's watchdog ticks while it has controllers to look at, rather
	// than being armed and disarmed with each slice (two system calls a
	// lockstep round trip). The first tick of a slice only marks it.
	if (!lane->watching) {
		lane->watching = true;
		lane->watchdog.arm(kWatchdog, kWatchdog);
	}
}

void on_watchdog(Run &run, Lane &lane)
{
	lane.watchdog.consume();
	if (lane.running.empty() || run.ending) {
		lane.watchdog.disarm();
		lane.watching = false;
		return;
	}
	// A copy: one stepping aside leaves the lane.
	const std::vector<Controller *> running = lane.running;
	for (Controller *c : running)
		if (look_at(run, *c))
			return; // (it scheduled the others)
	// A turn long enough to be worth another core: those waiting for this
	// one may take a free one now (lanes.cc).
	if (run.lanes.is_home(lane) && run.lanes.size() > 1)
		schedule(run);
}

// The watchdog's look at a running controller; true if it stepped aside.
bool look_at(Run &run, Controller &c)
{
	if (c.watchdog_look.slice != c.slices) {
		// A slice begun since the last tick: look from its start.
		c.watchdog_look.slice = c.slices;
		c.watchdog_look.cpu = c.slice().cpu_base; // read as it began: no system call
		c.watchdog_look.asleep_times = 0;
		return false;
	}
	int64_t cpu = c.cpu_now();
	// Asleep twice in a row, and not in a request of ours (waiting for its
	// child to register after a fork, it is asleep in our hands). (One
	// queued behind others on its core is runnable, not asleep.)
	bool asleep = cpu - c.watchdog_look.cpu <= kWatchdog / 100 && c.new_child.pid == 0 && proc_all_threads_asleep(c.pid);
	c.watchdog_look.asleep_times = asleep ? c.watchdog_look.asleep_times + 1 : 0;
	c.watchdog_look.cpu = cpu;
	return c.watchdog_look.asleep_times >= 2 && (block_if_all_waiting(run, c) || step_aside_if_asleep(run, c));
}

// The running controller, found making no progress: if every thread of it
// sleeps (and others may want the core), its time stands still and others
// go on. False if it is not asleep after all.
bool step_aside_if_asleep(Run &run, Controller &c)
{
	// (Not with a request unread: stepped aside, the world's time would
	// pass over it uncharged, and a replay, which has no such stop,
	// charged those milliseconds as CPU.)
	if (alive_controllers(run) < 2 || c.new_child.pid != 0 || !proc_all_threads_asleep(c.pid) || request_unread(c))
		return false;
	if (!c.runs_unhooked && !proc_maps_library(c.pid, "libtcs_preload")) {
		// It has exec'd a program that runs without tcs's hooks: from
		// now on it is the world's, in real time, till it ends.
		c.runs_unhooked = true;
		warn_once(run, "process " + std::to_string(c.pid) + " (" + proc_name(c.pid, c.name) +
			  ") runs in real time: it started a program without tcs's preload (a static program, or "
			  "LD_PRELOAD removed from its environment)");
	}
	run.devices.take_lazy_commands(c, -1, run.trace); // written before it fell asleep, at its time then
	int64_t cpu = c.cpu_now();
	c.watchdog_look.asleep_times = 0;
	run.lanes.leave(c);
	c.account(cpu, run.cfg.mode);
	c.publish_slice(cpu);
	trace_slice_end(run, c, "blocked", cpu);
	c.set_page_flag(TCS_PAGE_ASLEEP, true);
	block(run, c, { .recheck = true }, CtlMove::StepAside);
	schedule(run);
	return true;
}

// An asleep controller at its turn `at`: still asleep (stay aside), or
// runnable again. Its time while asleep is the world's, so its signal
// timers go off on time: a process in sigsuspend or waitpid waiting for
// its alarm (coreutils timeout) is woken by the signal as it would be.
bool still_asleep(Run &run, Controller &c, int64_t at)
{
	if (c.state() != CtlState::Asleep)
		return false;
	if (c.runs_unhooked)
		return true; // not ours to run: its end is all that is awaited
	if (c.next_timer() <= at) {
		advance(c, at);
		if (!run.ending)
			c.raise_due_timers();
	}
	if (proc_all_threads_asleep(c.pid))
		return true;
	wake_from_asleep(run, c);
	return false;
}

// Whatever woke c in the kernel (a pipe written, a signal sent) was done by
// the world or by another controller at its time then, which is at most
// its time now: an upper bound of the cause's time. (Controllers run ahead
// of the world within a step: a writer at 200.05 ms of a step begun at
// 200 ms woke a reader that then read 200 ms on its clock, before the write.)
// Its time is what its clocks read: in cpu mode an estimate may be ahead of
// its exact CPU (a reader read 7 us before the write, TCS_NO_TSC).
static int64_t latest_cause(const Run &run, const Controller &c)
{
	int64_t at = run.sim_ns;
	for (const auto &o : run.ctls)
		if (o.get() != &c)
			at = std::max(at, o->v_told(run.cfg.mode));
	return at;
}

// It woke by itself (or made a request): what it used meanwhile is its, and
// it is Ready as if it had been stopped. It was waiting all along, as in
// any wait: its time is at least that of what woke it (latest_cause: a
// reader of a pipe sees the data no earlier than it was written;
// TCS_PAGE_ASLEEP makes it ask before it looks at its clock). Not held as a
// stopped one is, it is answered only as it is resumed (answer()): answered
// at once, it ran on uncharged until its turn (18 us of a replayed run's
// start went missing from its record's first slice).
void wake_from_asleep(Run &run, Controller &c)
{
	int64_t cpu = c.cpu_now();
	c.account(cpu, run.cfg.mode);
	advance(c, latest_cause(run, c));
	c.publish_slice(cpu);
	c.woke_unheld = true;
	c.set_page_flag(TCS_PAGE_ASLEEP, false);
	awake(run, c);
}

} // namespace tcs
