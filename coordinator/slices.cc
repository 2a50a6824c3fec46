// A controller's slices: resumed with a CPU budget that ends at the world's
// next step (or further: scheduler.h), checked, preempted, accounted. Since
// each one's virtual time is its own CPU, each has a virtual CPU of its own
// whatever the host has.
//
// Accounting is exact: a budget is armed as a wall-clock timer (wall time is
// never less than the CPU a pinned process gets), and when it fires the
// controller's CPU-time clock says how far it really got. Short of its
// budget (it was blocked in the kernel, or another task ran), the timer is
// re-armed for the rest; past it, SIGSTOP, and the overshoot simply stays in
// its virtual time, so the next budget is that much shorter and no error
// accumulates (the TCS paper's §3.8 correction, with exact accounting).
#include "slices.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "asleep.h"
#include "clock_ns.h"
#include "exits.h"
#include "record_replay.h"
#include "proc_info.h"
#include "signal_timers.h"
#include "tcs/protocol.h"
#include "threads.h"
#include "waits.h"
#include "world_steps.h"
#include "transitions.h"

namespace tcs {

namespace {
// A controller that made no progress since the last check is asleep in the
// kernel on something real; check back ever less often, up to this.
constexpr int64_t kMaxRecheck = 10 * TCS_NS_PER_MS;
// How many times (20 us apart) a preempted child of a controller is looked
// at until it has stopped.
constexpr int kStopLooks = 50000;
// Bound on the learnt wall-versus-CPU lag of a slice.
constexpr int64_t kMaxLag = 200 * TCS_NS_PER_US;
// The most CPU a hook's return from a wait may take before its mark
// (a CPU-clock reading and a system call or two: tens of microseconds);
// beyond it, what runs is charged as the program's.
constexpr int64_t kMostWaitReturn = TCS_NS_PER_MS;
// How far a running controller's CPU reading may fall short of the wall
// time its slice has had (less the learnt lag) and still be taken as
// current: interrupts and the like on its core. Further short, it may be
// stale (or it slept in the kernel), and the check holds it to read it.
constexpr int64_t kStaleSlack = 50 * TCS_NS_PER_US;
} // namespace

int64_t wall_now()
{
	return clock_ns(CLOCK_MONOTONIC);
}

void start_slice_clock(Run &run, Controller &c)
{
	c.slice_wall = wall_now();
	Lane *lane = run.lanes.of(c);
	c.slice_host_cpu = lane && run.lanes.is_home(*lane) ? clock_ns(CLOCK_THREAD_CPUTIME_ID) : -1;
}

// The wall time c's slice has had on its core: less our own CPU there when
// we share it (the home lane), where a busy coordinator took most of it
// (a controller had 99 us of 367, and each such check held it).
static int64_t slice_wall_for_it(const Controller &c)
{
	int64_t wall = wall_now() - c.slice_wall;
	if (c.slice_host_cpu >= 0)
		wall -= clock_ns(CLOCK_THREAD_CPUTIME_ID) - c.slice_host_cpu;
	return wall;
}

void trace_slice_end(Run &run, Controller &c, const char *why, int64_t cpu, int64_t budget, int64_t overshoot)
{
	if (!run.trace.is_open())
		return;
	Trace::Slice s;
	s.v_start = c.trace_v_start;
	s.v_end = c.v();
	s.charged_ns = c.charged - c.trace_charged_start;
	s.cpu_ns = std::max<int64_t>(cpu - c.trace_cpu_start, 0);
	s.wall_start = c.trace_wall_start - run.wall_start;
	s.wall_end = wall_now() - run.wall_start;
	s.budget_ns = budget;
	s.overshoot_ns = overshoot;
	s.sim_ns = run.sim_ns;
	s.why = why;
	run.trace.slice(c.id, s);
}

// The CPU a request from c charges it up to. With one thread, its hook's
// claim: its CPU at the hook's entry, read there or extrapolated by the TSC
// from a reading at most 20 us old (cpu_estimate.c), which spares a system
// call on every request (a sleep's round trip keeps one reading of its CPU
// clock: the hook's exit mark). Taken if plausible (not before its slice
// began, nor more than the wall time since it was resumed, give or take the
// hooks' own); else, or with threads, its CPU clock says: another thread
// may have computed since this one's hook began, and that is charged too (a
// worker that held the core for 20 ms before main's BLOCK went out, seen:
// all of it went uncharged). An estimate too high (it slept in the kernel
// just after a hook) is made good by the next slice, which starts from it:
// never charged twice. In lockstep, where the charge is only a figure and
// the preload's exit marks are learnt (cpu_estimate.c), an implausible
// claim is held to those bounds instead: short of the slice's start it
// charges nothing, and the slices after make it good; beyond the wall time
// it charges that. No system call either way.
int64_t charge_point(Run &run, Controller &c, int64_t claimed)
{
	const int64_t base = c.slice().cpu_base;
	const bool one_thread = !c.multithreaded();
	const int64_t most = tcs_ns_add(base, wall_now() - c.resumed_wall + kClaimSlack);
	if (one_thread && claimed >= base && claimed <= most)
		return claimed;
	if (one_thread && run.cfg.mode == TCS_MODE_LOCKSTEP)
		return std::clamp(claimed, base, most);
	const int64_t now = std::max(base, c.cpu_now());
	if (one_thread)
		return std::clamp(claimed, base, now);
	// Read from here, the CPU of a thread on its core is behind by what it
	// computed since that core's last tick (1 to 10 ms) or its own last
	// system call; the claim, read in the process, is not (its threads
	// share one core, so no other ran meanwhile).
	return std::max(now, std::clamp(claimed, base, most));
}

int64_t request_v(Run &run, Controller &c, const ::tcs_msg &m)
{
	if (c.state() != CtlState::Running)
		return c.v();
	if (run.cfg.mode == TCS_MODE_LOCKSTEP)
		return std::clamp(m.v, c.v(), c.spun());
	int64_t heard = c.v_at_cpu(charge_point(run, c, m.cpu));
	return std::clamp(m.v, c.v(), std::max(c.v(), heard));
}

// Not to where the scheduler would stop it to let another run: that
// depends on how many cores there are, and its virtual time must not.
int64_t spin_limit(const Run &run, const Controller &c)
{
	int64_t limit = std::min(tcs_ns_add(c.v() - c.v() % run.cfg.step_ns, run.cfg.step_ns), c.next_timer());
	for (const Request &w : c.side_waits)
		if (w.deadline > c.v())
			limit = std::min(limit, w.deadline);
	return limit;
}

void resume(Run &run, Controller &c, int64_t target, int lane)
{
	run.lanes.take(c, lane);
	run.idle_timer.disarm();
	// c is held by SIGSTOP or waiting for its WAKE: its CPU clock is still.
	// Waking from a wait: its CPU clock has stood still since the BLOCK
	// (but for the hook's own tail, which the hook's mark excludes anyway).
	// Preempted: it begins where the reading that closed its last slice
	// ended, which may lack the end of its stop (see preempt).
	int64_t cpu = c.cpu_at_end >= 0 ? c.cpu_at_end : c.cpu_now();
	c.cpu_at_end = -1;
	c.publish_slice(cpu);
	if (run.cfg.mode == TCS_MODE_LOCKSTEP) // (before its WAKE: it may spin at once)
		c.limit_spin(run.replaying ? TCS_NEVER : spin_limit(run, c)); // (replaying: the record's stops)
	start_slice_clock(run, c);
	c.resumed_wall = c.slice_wall;
	if (run.trace.is_open()) {
		c.trace_cpu_start = cpu;
		c.trace_wall_start = c.resumed_wall;
		c.trace_v_start = c.v();
		c.trace_charged_start = c.charged;
	}
	run.wires.advance(c.v(), run.sim_ns, run.world.get());
	deliver(c); // what its sensors have due by now is in their fds
	c.hook_marks_return = c.wait.owed && !c.multithreaded(); // (roundtrip.c)
	c.woke_unheld = false;
	// Other threads' waits due by now are answered first: a thread that
	// spun to their time yields to them once answered, and finds them
	// answered (spin.c).
	end_side_waits(run, c);
	if (c.wait.owed)
		send_wake(run, c);
	if (c.stopped)
		let_go(run, c);
	move(run, c, CtlMove::Resume);
	c.budgeted = false;
	budget_to(run, c, target);
	budget_to_next_timer(run, c); // and no further than its own next signal
	if (!c.budgeted)
		arm_watchdog(run, c); // (a budget's own checks look for sleep)
	// Lockstep: computation is free, so no budget; it runs until it waits.
	// Nor is there one when nothing else will ever need the core.
}

void budget_to(Run &run, Controller &c, int64_t target)
{
	Lane *lane = run.lanes.of(c);
	if (run.cfg.mode != TCS_MODE_CPU || target == TCS_NEVER || c.budgeted || !lane)
		return;
	// From the slice's start: what it used since counts against it.
	double need = std::ceil((double)(target - c.slice().v_base) / c.scale);
	c.budget = std::max<int64_t>((int64_t)need, 1);
	c.budgeted = true;
	c.checked_used = -1;
	// Wall time runs ahead of the CPU the controller gets (our own work on
	// its core); arm that much later, as learnt so far, so one timer
	// usually ends the slice (the TCS paper's ε correction).
	c.check_interval = std::max(c.slice_wall + c.budget + c.lag_ns - wall_now(), kMinSlice);
	lane->budget.arm(c.check_interval);
}

// It ended before it could stop: its slice ends with it, traced as its
// exit (on_pidfd does so while it is in its lane: leaving first, the last
// slice of a controller that exited as a check held it went unrecorded).
static void died_in_slice(Run &run, Controller &c)
{
	on_pidfd(run, c);
	run.lanes.leave(c); // (gone by now unless some thread of it lingers)
}

// Its slice's CPU, held still (hold_still left the stop's cost out). One
// that had reached its budget by the kernel's count and falls short only
// by what was left out is charged the rest of it: resumed for a sliver
// that short, it would only be stopped again. (By what was left out, not
// by a stop's cost: a stop leaves out less when the program read its clock
// just before it, and a charge back beyond what was left out is lost.)
static int64_t used_after_hold(Run &run, Controller &c)
{
	int64_t used = c.slice_cpu(c.cpu_now());
	const Lane *lane = run.lanes.of(c);
	if (lane && c.budgeted && used < c.budget && used + c.left_out() >= c.budget) {
		c.leave_out(used - c.budget);
		used = c.budget;
	}
	return used;
}

void on_budget(Run &run, Lane &lane)
{
	if (!lane.budget.consume() || lane.running.size() != 1)
		return; // (budgets are cpu mode's, where a lane runs one at most)
	Controller &c = *lane.running.front();
	int64_t cpu = c.cpu_now();
	int64_t used = c.slice_cpu(cpu);
	// All it ran in the slice, the hooks' too: what wall time is set
	// against. (Against its own CPU alone, a slice that began in a wake's
	// hook looked stale just after the hook's mark and was held: a stop
	// charges ~85 us of kernel work to the stopped thread, there where
	// the program's loop had read its clock, so it ran that much late.)
	int64_t ran = std::max<int64_t>(cpu - c.slice().cpu_base, 0);
	bool held = false;
	if (used < c.budget && slice_wall_for_it(c) - c.lag_ns - ran > kStaleSlack &&
	    !proc_all_threads_asleep(c.pid)) {
		// Short of the wall time the slice has had, and a thread of it is
		// on its core: read from here, its CPU clock is behind by what it
		// computed since that core's last tick (1 to 10 ms apart) or its
		// own last system call, as the kernel brings a running thread's
		// count up to date only then. Computing without system calls, it
		// read 0 after 1.8 ms and overran its budget by 3.4 ms. Held
		// still, its clock is exact. (Not on every check: each stop
		// costs it CPU in the kernel and the coordinator wall time.)
		if (!hold_still(run, c)) {
			died_in_slice(run, c);
			return;
		}
		held = true;
		used = used_after_hold(run, c);
	}
	if (used >= c.budget && used < kMostWaitReturn && c.returning_from_wait()) {
		// Still in the hook of the wait that its WAKE ended: what it ran
		// is the hook's own, which its mark will leave uncharged, and a
		// budget is the program's own computation. Preempted there, all
		// of it was charged as the program's (a 1 kHz loop woke 116 us
		// late by its clock, with a 25 us budget to the world's step, on
		// a machine whose CPU-clock reading is slow). Look again soon.
		if (held)
			let_go(run, c);
		lane.budget.arm(kMinSlice);
		return;
	}
	if (c.checked_used < 0) {
		// First check of the slice: learn the lag (an integrating
		// controller on what was missing or too much; bounded).
		c.lag_ns = std::clamp<int64_t>(c.lag_ns + (c.budget - used) / 4, 0, kMaxLag);
	}
	if (used >= c.budget && !held) {
		// Judged again held, as it will be preempted held: what its slice
		// leaves out (the stop's cost, the runtime's own CPU, a hook's
		// tail) grows meanwhile, and one short of its budget by that is
		// not preempted but given the rest (a preemption short of its
		// budget leaves it behind the world's step it was to reach).
		if (!hold_still(run, c)) {
			died_in_slice(run, c);
			return;
		}
		held = true;
		used = used_after_hold(run, c);
	}
	if (used >= c.budget) {
		preempt(run, c);
		schedule(run);
		return;
	}
	if (held)
		let_go(run, c);
	// Short of its budget: it was asleep in the kernel, or the core was
	// busy with something else. If it made no progress at all and sleeps
	// still, others may have the core meanwhile (asleep.cc).
	if (used == c.checked_used && (block_if_all_waiting(run, c) || step_aside_if_asleep(run, c)))
		return;
	// Else give it the rest.
	int64_t rest = std::max(c.budget - used, kMinSlice);
	c.check_interval = used > std::max<int64_t>(c.checked_used, 0)
				   ? rest
				   : std::min(2 * c.check_interval, std::max(rest, kMaxRecheck));
	c.checked_used = used;
	lane.budget.arm(c.check_interval);
}

// After its SIGSTOP: true once c has stopped, false if it died first. It
// stops when it next runs, which is once we let go of its core.
bool wait_until_stopped(Run &run, Controller &c)
{
	if (c.parent_id == 0) {
		siginfo_t si = {};
		int r;
		do
			r = waitid(P_PID, (id_t)c.pid, &si, WSTOPPED | WEXITED | WNOWAIT);
		while (r < 0 && errno == EINTR);
		if (r < 0 || si.si_code != CLD_STOPPED)
			return false;
		si = {};
		waitid(P_PID, (id_t)c.pid, &si, WSTOPPED);
		return true;
	}
	// A child of a controller is its parent's to wait for: waitid cannot
	// see it stop (it fails with ECHILD, and the controller was taken for
	// dead and left stopped), and nothing tells of its stop but /proc. So
	// look, between waits on its pidfd (its end ends them at once) that
	// let go of the core meanwhile.
	for (int i = 0; i < kStopLooks; i++) {
		struct pollfd ended = { c.pidfd.get(), POLLIN, 0 };
		const struct timespec look_again = { 0, i == 0 ? 0 : 20 * TCS_NS_PER_US };
		if (ppoll(&ended, 1, &look_again, nullptr) > 0)
			return false;
		if (proc_all_threads_stopped(c.pid))
			return true;
	}
	return true; // (asleep uninterruptibly for a second: it stops on waking)
}

bool hold_still(Run &run, Controller &c)
{
	if (run.cfg.realtime.stop_delay_ns > 0) {
		// (At most 100 ms: TCS_STOP_DELAY_US.)
		struct timespec late = { 0, (long)run.cfg.realtime.stop_delay_ns };
		nanosleep(&late, nullptr);
	}
	kill(c.pid, SIGSTOP);
	if (!wait_until_stopped(run, c))
		return false;
	// What the stop cost it in the kernel is CPU it never used on the
	// robot: not charged (stop_cost.h). Its continuation's likewise. The
	// cost is a mean: never more than the slice's CPU so far (a charge
	// could not be given back past that: tcs_less_own never adds), nor
	// than it ran since its clock last told it a time, or what it does
	// next would be stamped before that time. Nor is it left out of a
	// slice still in its wait's hook: the hook's mark, when it comes,
	// leaves out all the slice's CPU before it, the stop's included.
	Lane *lane = run.lanes.of(c);
	if (lane && lane->stop_cost.stop_ns > 0 && !c.returning_from_wait()) {
		const int64_t cpu = c.cpu_now();
		c.leave_out(std::min({ lane->stop_cost.stop_ns, c.cpu_since_told(cpu), c.slice_cpu(cpu) }));
	}
	return true;
}

void let_go(Run &run, Controller &c)
{
	Lane *lane = run.lanes.of(c);
	if (lane && !c.returning_from_wait()) // (as in hold_still)
		c.leave_out(lane->stop_cost.continue_ns);
	kill(c.pid, SIGCONT);
	c.stopped = false;
}

void preempt(Run &run, Controller &c)
{
	run.lanes.leave(c);
	c.stopped = true;
	move(run, c, CtlMove::Preempt);
	c.stats.preemptions++;
	// Read from here, a process's CPU clock is as its threads' counts were
	// last brought up to date (by a tick of their core, or a switch), and
	// the stop is reported before the stopping thread has left its core:
	// the reading may lack up to a tick of its CPU (194 us seen), which
	// the clock shows by the next resume. The next slice begins at this
	// reading, so that it charges what this one lacked: were it to begin
	// at a new one, that CPU would be nobody's (a burn's 56 ms of CPU came
	// out 26 us short of the kernel's).
	int64_t cpu = c.cpu_now();
	int64_t budget = c.budget;
	int64_t overshoot = c.slice_cpu(cpu) - budget; // before account() closes the slice
	c.account(cpu, run.cfg.mode);
	c.cpu_at_end = cpu;
	trace_slice_end(run, c, "preempted", cpu, budget, overshoot);
	journal_stop(run, c, overshoot);
	if (!run.ending)
		c.raise_due_timers(); // pending until it continues
}

} // namespace tcs
