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
#include "coordinator.h"
#include "proc_info.h"

namespace tcs {

void Coordinator::arm_watchdog(Controller &c)
{
	// Only worth it when someone else may be waiting for the core, or
	// when its threads may all be waiting.
	Lane *lane = lanes_.of(c);
	if (!lane || (alive_controllers() < 2 && c.side.empty()))
		return;
	// A lane's watchdog ticks while it has controllers to look at, rather
	// than being armed and disarmed with each slice (two system calls a
	// lockstep round trip). The first tick of a slice only marks it.
	if (!lane->watching) {
		lane->watching = true;
		lane->watchdog.arm(kWatchdog, kWatchdog);
	}
}

void Coordinator::on_watchdog(Lane &lane)
{
	lane.watchdog.consume();
	if (lane.running.empty() || ending_) {
		lane.watchdog.disarm();
		lane.watching = false;
		return;
	}
	// A copy: one stepping aside leaves the lane.
	const std::vector<Controller *> running = lane.running;
	for (Controller *c : running)
		if (look_at(*c))
			return; // (it scheduled the others)
	// A turn long enough to be worth another core: those waiting for this
	// one may take a free one now (lanes.cc).
	if (lanes_.is_home(lane) && lanes_.size() > 1)
		schedule();
}

// The watchdog's look at a running controller; true if it stepped aside.
bool Coordinator::look_at(Controller &c)
{
	if (c.watched_slice != c.slices) {
		// A slice begun since the last tick: look from its start.
		c.watched_slice = c.slices;
		c.watch_cpu = c.slice().cpu_base; // read as it began: no system call
		c.asleep_looks = 0;
		return false;
	}
	int64_t cpu = c.cpu_now();
	// Asleep twice in a row, and not in a request of ours (waiting for its
	// child to register after a fork, it is asleep in our hands). (One
	// queued behind others on its core is runnable, not asleep.)
	bool asleep = cpu - c.watch_cpu <= kWatchdog / 100 && c.awaiting_child == 0 && proc_all_threads_asleep(c.pid);
	c.asleep_looks = asleep ? c.asleep_looks + 1 : 0;
	c.watch_cpu = cpu;
	return c.asleep_looks >= 2 && (block_if_all_waiting(c) || step_aside_if_asleep(c));
}

// The running controller, found making no progress: if every thread of it
// sleeps (and others may want the core), its time stands still and others
// go on. False if it is not asleep after all.
bool Coordinator::step_aside_if_asleep(Controller &c)
{
	if (alive_controllers() < 2 || c.awaiting_child != 0 || !proc_all_threads_asleep(c.pid))
		return false;
	if (!c.outside && !proc_maps_library(c.pid, "libtcs_preload")) {
		// It has exec'd a program that runs without tcs's hooks: from
		// now on it is the world's, in real time, till it ends.
		c.outside = true;
		warn_once("process " + std::to_string(c.pid) + " (" + proc_name(c.pid, c.name) +
			  ") runs in real time: it started a program without tcs's preload (a static program, or "
			  "LD_PRELOAD removed from its environment)");
	}
	devices_.take_lazy_commands(c, -1, trace_); // written before it fell asleep, at its time then
	int64_t cpu = c.cpu_now();
	c.asleep_looks = 0;
	lanes_.leave(c);
	c.account(cpu, cfg_.mode);
	c.publish_slice(cpu);
	trace_slice_end(c, "blocked", cpu);
	c.asleep = true;
	c.set_page_flag(TCS_PAGE_ASLEEP, true);
	c.state = CtlState::Blocked;
	c.wait.deadline = TCS_NEVER;
	c.wait.recheck = true;
	c.wait.rechecked_at = sim_ns_;
	c.wait.devices = false;
	c.wait.for_child = false; // its last wait's: it is in none of ours now
	c.wait.active = false;
	schedule();
	return true;
}

// An asleep controller at its turn `at`: still asleep (stay aside), or
// runnable again. Its time while asleep is the world's, so its signal
// timers go off on time: a process in sigsuspend or waitpid waiting for
// its alarm (coreutils timeout) is woken by the signal as it would be.
bool Coordinator::still_asleep(Controller &c, int64_t at)
{
	if (!c.asleep)
		return false;
	if (c.outside)
		return true; // not ours to run: its end is all that is awaited
	if (c.next_timer() <= at) {
		c.v = std::max(c.v, at);
		if (!ending_)
			c.raise_due_timers();
	}
	if (proc_all_threads_asleep(c.pid))
		return true;
	wake_from_asleep(c);
	return false;
}

// It woke by itself (or made a request): what it used meanwhile is its, and
// it is Ready as if it had been stopped. It was waiting all along, as in
// any wait: its time is at least the world's now (a reader of a pipe sees
// the data no earlier than it was written; TCS_PAGE_ASLEEP makes it ask
// before it looks at its clock).
void Coordinator::wake_from_asleep(Controller &c)
{
	int64_t cpu = c.cpu_now();
	c.account(cpu, cfg_.mode);
	c.v = std::max(c.v, sim_ns_);
	c.publish_slice(cpu);
	c.asleep = false;
	c.set_page_flag(TCS_PAGE_ASLEEP, false);
	c.state = CtlState::Ready;
	c.wait.recheck = false;
	c.wake_pending = false;
}

} // namespace tcs
