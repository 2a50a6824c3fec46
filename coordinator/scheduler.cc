// Conservative synchronisation (DESIGN.md §2). The world steps from S to
// S+dt only when every controller has reached S+dt (then it is held by
// SIGSTOP) or waits for a time at or past it. Until then the controllers
// that are behind run, one on each core tcs may use (lanes.cc), each with a
// CPU budget that ends exactly at S+dt; since each one's virtual time is its
// own CPU, each has a virtual CPU of its own whatever the host has.
//
// Accounting is exact: a budget is armed as a wall-clock timer (wall time is
// never less than the CPU a pinned process gets), and when it fires the
// controller's CPU-time clock says how far it really got. Short of its
// budget (it was blocked in the kernel, or another task ran), the timer is
// re-armed for the rest; past it, SIGSTOP, and the overshoot simply stays in
// its virtual time, so the next budget is that much shorter and no error
// accumulates (the TCS paper's §3.8 correction, with exact accounting).
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "clock_ns.h"
#include "coordinator.h"
#include "proc_info.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"

namespace tcs {

namespace {
// A controller that made no progress since the last check is asleep in the
// kernel on something real; check back ever less often, up to this.
constexpr int64_t kMaxRecheck = 10 * TCS_NS_PER_MS;
// The longest the world computes before the event loop gets a turn.
constexpr int64_t kAdvanceSlice = 20 * TCS_NS_PER_MS;
// A world step that costs more wall time than this is heavy.
constexpr int64_t kHeavyStep = 100 * TCS_NS_PER_US;
// How long a child may run unregistered before it is said to run in real
// time (a program still loading has not registered yet).
constexpr int64_t kRegistrationGrace = 200 * TCS_NS_PER_MS;
// How many times (20 us apart) a preempted child of a controller is looked
// at until it has stopped.
constexpr int kStopLooks = 50000;
// Bound on the learnt wall-versus-CPU lag of a slice.
constexpr int64_t kMaxLag = 200 * TCS_NS_PER_US;
// How far a running controller's CPU reading may fall short of the wall
// time its slice has had (less the learnt lag) and still be taken as
// current: interrupts and the like on its core. Further short, it may be
// stale (or it slept in the kernel), and the check holds it to read it.
constexpr int64_t kStaleSlack = 50 * TCS_NS_PER_US;
// How far behind real time an idle world may fall and catch up.
constexpr int64_t kIdleCatchUp = 50 * TCS_NS_PER_MS;
} // namespace

void Coordinator::schedule()
{
	if (ending_ || held_ || awaiting_grant_ || !fatal_ || hearing_)
		return;
	for (;;) {
		const int64_t target = sim_ns_ + cfg_.step_ns;
		Controller *best = nullptr;
		int64_t best_at = TCS_NEVER;
		int64_t next_event = TCS_NEVER;
		bool any = false, recheck = false, running = false;
		for (auto &cp : ctls_) {
			Controller &c = *cp;
			if (c.state == CtlState::Exited)
				continue;
			any = true;
			if (c.state == CtlState::Running) {
				running = true;
				continue;
			}
			int64_t at = next_run_at(c);
			recheck |= c.state == CtlState::Blocked && (c.recheck || c.others_asleep ||
								    std::any_of(c.side.begin(), c.side.end(), [](const SideWait &w) {
									    return (w.flags & TCS_BLOCK_RECHECK) != 0;
								    }));
			if (at < target && at < best_at) {
				best = &c;
				best_at = at;
			} else if (at >= target) {
				next_event = std::min(next_event, at);
			}
		}
		if (!any) {
			// Everyone has exited: run() notices; served, the world goes
			// on at real-time speed until someone attaches, here or at an
			// agent; with controllers at an agent, at the step protocol's
			// pace (an agent answers at once: its host sets the pace).
			bool remote = std::any_of(agents_.begin(), agents_.end(),
						  [](const auto &a) { return !a.second.programs.empty(); });
			if (cfg_.step_agent || remote) {
				if (!advance_to(target))
					return;
				continue;
			}
			if (cfg_.serve)
				arm_idle_step();
			return;
		}
		// The best of those behind takes a free core, and the next one
		// the next (each runs to the step at most, none waits for another).
		const int lane = best ? free_lane(*best) : -1;
		if (best && lane < 0)
			return; // every core is taken: the next to leave one goes on
		if (best && best->asleep && still_asleep(*best, best_at)) {
			// Looked at: still asleep, its turn passes for this step.
			best->rechecked_at = sim_ns_;
			best->kicked_at = TCS_NEVER;
			continue;
		}
		if (best) {
			if (best->state == CtlState::Blocked && (!best->side.empty() || best->others_asleep)) {
				// Several threads wait: end those due (threads.cc).
				if (!wake_threads(*best, best_at)) {
					best->rechecked_at = sim_ns_;
					for (SideWait &w : best->side)
						w.rechecked_at = sim_ns_;
					continue;
				}
			} else if (best->state == CtlState::Blocked && best->next_timer() <= best_at && best->next_timer() < best->deadline) {
				// A signal timer is due in its wait: send it, and wake it to
				// re-check (its wait ends with EINTR if a handler ran).
				best->v = std::max(best->v, best_at);
				best->wake_arg = (int64_t)due_timer_signals(*best);
				best->rechecked_at = sim_ns_;
				wake(*best, best->v, TCS_WAKE_SIGNAL);
			} else if (best->state == CtlState::Blocked) {
				bool due = best->deadline < target;
				best->rechecked_at = sim_ns_;
				wake(*best, due ? std::max(best->v, best->deadline) : best_at,
				     due || best->wants_devices ? TCS_WAKE_DEADLINE : TCS_WAKE_RECHECK);
			}
			if (best->sync_pending && !complete_sync(*best))
				continue; // a read that must wait for its next record
			resume(*best, run_until(*best, target), lane);
			continue;
		}
		if (running)
			return; // the world steps once those running have reached it

		// Nobody can run before target: the world steps.
		if (next_event == TCS_NEVER) {
			// Every controller waits for something only the real world
			// can end (some looked at each step: asleep outside the hooks,
			// or in a wait only a re-check can see end): let virtual time
			// pass at real-time speed, and hear their channels meanwhile.
			arm_idle_step();
			return;
		}
		int64_t next = target;
		// Skip steps nobody acts in (not with peers: each step is a barrier).
		if (!recheck && next_event > target && agents_.empty() && !cfg_.step_agent)
			next = next_event - next_event % cfg_.step_ns;
		if (!advance_to(next))
			return;
	}
}

int64_t Coordinator::next_run_at(const Controller &c) const
{
	if (c.state == CtlState::Ready || c.state == CtlState::Running)
		return c.v;
	bool side_recheck = false, side_devices = false;
	for (const SideWait &w : c.side) {
		side_recheck |= (w.flags & TCS_BLOCK_RECHECK) && w.rechecked_at < sim_ns_;
		side_devices |= (w.flags & TCS_BLOCK_DEVICES) != 0;
		if (w.wake_reason)
			return c.v;
	}
	if (((c.recheck || c.others_asleep) && c.rechecked_at < sim_ns_) || side_recheck)
		return std::max(c.v, sim_ns_);
	int64_t until = std::min({ c.deadline, c.next_timer(), side_next(c), c.kicked_at });
	if (c.wants_devices || side_devices)
		until = std::min(until, next_record_due(c));
	return until == TCS_NEVER ? TCS_NEVER : std::max(c.v, until);
}

// How far c may run before someone else needs the core: another
// controller's next turn, the end of the run, or the world's next step that
// matters. Never short of the step boundary `target`. Stopping a controller
// costs it real CPU (the timer interrupt, the stop and the continue run on
// its account), so it is not stopped at boundaries nobody needs.
int64_t Coordinator::run_until(const Controller &c, int64_t target) const
{
	int64_t horizon = world_horizon();
	for (const auto &o : ctls_)
		if (o.get() != &c && o->state != CtlState::Exited)
			horizon = std::min(horizon, next_run_at(*o));
	if (cfg_.duration_ns >= 0)
		horizon = std::min(horizon, cfg_.duration_ns);
	return std::max(target, horizon);
}

// The next step boundary the world needs controllers to stop at. The
// built-in empty world has nothing to compute, so none.
int64_t Coordinator::world_horizon() const
{
	return TCS_NEVER;
}

int64_t Coordinator::wall_now()
{
	return clock_ns(CLOCK_MONOTONIC);
}

void Coordinator::trace_slice_end(Controller &c, const char *why, int64_t cpu, int64_t budget, int64_t overshoot)
{
	if (!trace_.is_open())
		return;
	Trace::Slice s;
	s.v_start = c.trace_v_start;
	s.v_end = c.v;
	s.charged_ns = c.charged - c.trace_charged_start;
	s.cpu_ns = std::max<int64_t>(cpu - c.trace_cpu_start, 0);
	s.wall_start = c.trace_wall_start - wall_start_;
	s.wall_end = wall_now() - wall_start_;
	s.budget_ns = budget;
	s.overshoot_ns = overshoot;
	s.sim_ns = sim_ns_;
	s.why = why;
	trace_.slice(c.id, s);
}

bool Coordinator::advance_to(int64_t next)
{
	// An agent's world is stepped by its host: answer its grant instead.
	if (cfg_.step_agent) {
		answer_grant();
		return false;
	}
	// A host steps only when every agent has answered (on_step_host goes on).
	if (!agents_answered())
		return false;
	if (cfg_.duration_ns >= 0 && next >= cfg_.duration_ns)
		next = std::max(cfg_.duration_ns, sim_ns_);
	if (!world_) {
		// An empty world: nothing to compute on the way.
		steps_ += (next - sim_ns_ + cfg_.step_ns - 1) / cfg_.step_ns;
		sim_ns_ = next;
	}
	// A heavy world (a step costing more than a budget timer's slack) is
	// computed at normal priority; see coordinator_fifo().
	bool heavy = world_ && world_->last_step_wall_ns() > kHeavyStep && sim_ns_ < next;
	if (heavy)
		coordinator_fifo(rt_, false);
	// At most a slice of wall time here: the rest after the event loop has
	// had its turn (a controller asleep for hours must not make tcs deaf to
	// Ctrl-C or to a controller's death while the world computes them).
	const int64_t yield_at = wall_now() + kAdvanceSlice;
	bool yielded = false;
	while (sim_ns_ < next) {
		if (auto s = step_world(); !s) {
			fatal_ = s;
			break;
		}
		if (!agents_answered())
			break; // the next step waits for the agents' answers
		if (sim_ns_ < next && wall_now() >= yield_at) {
			continue_timer_.arm(1);
			yielded = true;
			break;
		}
	}
	if (heavy)
		coordinator_fifo(rt_, true);
	if (!fatal_ || yielded)
		return false;
	if (cfg_.duration_ns >= 0 && sim_ns_ >= cfg_.duration_ns) {
		begin_end(EndReason::Duration);
		return false;
	}
	return agents_answered();
}

// The next step of a world that runs at real-time speed, on a wall clock
// anchored where it began to, so that the time steps take (and this
// coordinator waiting for its core, under load) is not lost from it. Far
// behind (the machine paused), it starts again from now.
void Coordinator::arm_idle_step()
{
	int64_t now = wall_now();
	if (sim_ns_ != idle_.next_sim || now - idle_.wall_for(sim_ns_) > kIdleCatchUp)
		idle_ = IdlePace{ now, sim_ns_, 0 };
	idle_.next_sim = sim_ns_ + cfg_.step_ns;
	idle_timer_.arm(std::max<int64_t>(idle_.wall_for(idle_.next_sim) - now, 1));
}

void Coordinator::on_idle()
{
	idle_timer_.consume();
	if (any_running() || ending_ || held_)
		return;
	if (advance_to(sim_ns_ + cfg_.step_ns))
		schedule();
}

void Coordinator::wake(Controller &c, int64_t v, uint16_t reason)
{
	c.v = std::max(c.v, v);
	c.state = CtlState::Ready;
	c.recheck = false;
	c.kicked_at = TCS_NEVER;
	c.wants_devices = false;
	c.wake_pending = true;
	c.wake_reason = reason;
}

// Every WAKE goes out here: through c's mailbox if the request came that
// way and c still spins for it, else on channel fd (with pass_fd, if not
// -1). A full or closed channel means the controller is gone or hostile;
// its pidfd or its next message will tell.
void Coordinator::send_answer(Controller &c, int fd, const ::tcs_msg &m, int pass_fd)
{
	if (fd == c.channel.get()) {
		if (pass_fd >= 0)
			c.mailbox.park(); // (an fd only the channel can carry)
		if (c.mailbox.answer(m))
			return;
	}
	struct tcs_msg_io io;
	tcs_msg_io_send(&io, &m, sizeof m, pass_fd);
	(void)sendmsg(fd, &io.mh, MSG_DONTWAIT | MSG_NOSIGNAL);
}

void Coordinator::send_wake(Controller &c)
{
	int fd = c.wait_fd >= 0 ? c.wait_fd : c.channel.get();
	channel_state(c, fd).unanswered = 0;
	struct tcs_msg m = tcs_msg_make(TCS_MSG_WAKE, c.wait_seq);
	m.kind = c.wake_reason;
	m.flags = TCS_WAKE_STARTS_SLICE;
	m.v = c.v;
	m.arg = c.wake_arg;
	send_answer(c, fd, m, c.wake_fd);
	if (c.wake_fd >= 0) {
		close(c.wake_fd);
		c.wake_fd = -1;
	}
	if (c.in_block && trace_.is_open())
		trace_.wait(c.id, c.wait_kind, c.wait_requested_at, c.deadline, c.v, c.wait_absolute);
	c.in_block = false;
	c.wake_arg = 0;
	c.wake_pending = false;
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
int64_t Coordinator::charge_point(Controller &c, int64_t claimed)
{
	const int64_t base = c.slice().cpu_base;
	const bool one_thread = !c.multithreaded();
	const int64_t most = tcs_ns_add(base, wall_now() - c.resumed_wall + kClaimSlack);
	if (one_thread && claimed >= base && claimed <= most)
		return claimed;
	if (one_thread && cfg_.mode == TCS_MODE_LOCKSTEP)
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

int64_t Coordinator::request_v(Controller &c, const ::tcs_msg &m)
{
	if (c.state != CtlState::Running || cfg_.mode != TCS_MODE_CPU)
		return c.v;
	int64_t heard = tcs_ns_add(c.slice().v_base, tcs_scale_cpu(c.slice_cpu(charge_point(c, m.cpu)), c.scale));
	return std::clamp(m.v, c.v, std::max(c.v, heard));
}

void Coordinator::resume(Controller &c, int64_t target, int lane)
{
	take_lane(c, lane);
	idle_timer_.disarm();
	// c is held by SIGSTOP or waiting for its WAKE: its CPU clock is still.
	// Waking from a wait: its CPU clock has stood still since the BLOCK
	// (but for the hook's own tail, which the hook's mark excludes anyway).
	int64_t cpu = c.cpu_at_block >= 0 ? c.cpu_at_block : c.cpu_now();
	c.cpu_at_block = -1;
	c.publish_slice(cpu);
	c.resumed_wall = c.slice_wall = wall_now();
	if (trace_.is_open()) {
		c.trace_cpu_start = cpu;
		c.trace_wall_start = c.resumed_wall;
		c.trace_v_start = c.v;
		c.trace_charged_start = c.charged;
	}
	deliver(c); // what its sensors have due by now is in their fds
	if (c.wake_pending)
		send_wake(c);
	end_side_waits(c); // other threads' waits due by now
	if (c.stopped) {
		kill(c.pid, SIGCONT);
		c.stopped = false;
	}
	c.state = CtlState::Running;
	c.budgeted = false;
	if (cfg_.mode == TCS_MODE_CPU && target != TCS_NEVER) {
		double need = std::ceil((double)(target - c.v) / c.scale);
		c.budget = std::max<int64_t>((int64_t)need, 1);
		c.budgeted = true;
		c.checked_used = -1;
		// Wall time runs ahead of the CPU the controller gets (our own
		// work on its core); arm that much later, as learnt so far, so one
		// timer usually ends the slice (the TCS paper's ε correction).
		c.check_interval = std::max(c.budget + c.lag_ns, kMinSlice);
		lanes_[(size_t)lane]->budget.arm(c.check_interval);
	}
	budget_to_next_timer(c); // and no further than its own next signal
	if (!c.budgeted)
		arm_watchdog(c); // (a budget's own checks look for sleep)
	// Lockstep: computation is free, so no budget; it runs until it waits.
	// Nor is there one when nothing else will ever need the core.
}

void Coordinator::on_budget(Lane &lane)
{
	if (!lane.budget.consume() || lane.running.size() != 1)
		return; // (budgets are cpu mode's, where a lane runs one at most)
	Controller &c = *lane.running.front();
	int64_t used = c.slice_cpu(c.cpu_now());
	bool held = false;
	if (used < c.budget && wall_now() - c.slice_wall - c.lag_ns - used > kStaleSlack &&
	    !proc_all_threads_asleep(c.pid)) {
		// Short of the wall time the slice has had, and a thread of it is
		// on its core: read from here, its CPU clock is behind by what it
		// computed since that core's last tick (1 to 10 ms apart) or its
		// own last system call, as the kernel brings a running thread's
		// count up to date only then. Computing without system calls, it
		// read 0 after 1.8 ms and overran its budget by 3.4 ms. Held
		// still, its clock is exact. (Not on every check: the stop's own
		// work in the kernel is charged to the thread it stops.)
		if (!hold(c)) {
			leave_lane(c);
			on_pidfd(c); // it died before it could stop
			return;
		}
		held = true;
		used = c.slice_cpu(c.cpu_now());
	}
	if (c.checked_used < 0) {
		// First check of the slice: learn the lag (an integrating
		// controller on what was missing or too much; bounded).
		c.lag_ns = std::clamp<int64_t>(c.lag_ns + (c.budget - used) / 4, 0, kMaxLag);
	}
	if (used >= c.budget) {
		preempt(c, held);
		schedule();
		return;
	}
	if (held) {
		kill(c.pid, SIGCONT);
		c.stopped = false;
	}
	// Short of its budget: it was asleep in the kernel, or the core was
	// busy with something else. If it made no progress at all and sleeps
	// still, others may have the core meanwhile (asleep.cc).
	if (used == c.checked_used && (block_if_all_waiting(c) || step_aside_if_asleep(c)))
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
bool Coordinator::wait_until_stopped(Controller &c)
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
	// dead and left stopped). So look, letting go of the core meanwhile.
	for (int i = 0; i < kStopLooks; i++) {
		struct pollfd ended = { c.pidfd.get(), POLLIN, 0 };
		if (poll(&ended, 1, 0) > 0)
			return false;
		if (proc_all_threads_stopped(c.pid))
			return true;
		struct timespec pause = { 0, 20 * TCS_NS_PER_US };
		nanosleep(&pause, nullptr);
	}
	return true; // (asleep uninterruptibly for a second: it stops on waking)
}

bool Coordinator::hold(Controller &c)
{
	if (cfg_.realtime.stop_delay_ns > 0) {
		// (At most 100 ms: TCS_STOP_DELAY_US.)
		struct timespec late = { 0, (long)cfg_.realtime.stop_delay_ns };
		nanosleep(&late, nullptr);
	}
	kill(c.pid, SIGSTOP);
	return wait_until_stopped(c);
}

void Coordinator::preempt(Controller &c, bool held)
{
	leave_lane(c);
	if (!held && !hold(c)) {
		on_pidfd(c); // it died before it could stop
		return;
	}
	c.stopped = true;
	c.state = CtlState::Ready;
	c.stats.preemptions++;
	int64_t cpu = c.cpu_now();
	int64_t budget = c.budget;
	int64_t overshoot = c.slice_cpu(cpu) - budget; // before account() closes the slice
	c.account(cpu, cfg_.mode);
	trace_slice_end(c, "preempted", cpu, budget, overshoot);
	deliver_due_timers(c); // pending until it continues
}

void Coordinator::on_block(Controller &c, const ::tcs_msg &m, int fd, pid_t tid)
{
	ChannelState &st = channel_state(c, fd);
	if (!ending_ && st.early_ahead != 0 && st.early_ahead == m.seq) {
		// Another thread ended this wait before it began.
		st.early_ahead = 0;
		c.stats.waits++;
		SideWait w = side_wait_of(m, fd, tid, c.v, sim_ns_);
		w.wake_reason = TCS_WAKE_EARLY;
		answer_side(c, w);
		if (c.state == CtlState::Blocked) {
			// (It was asleep outside the hooks: it runs again.)
			demote_wait(c);
			c.state = CtlState::Ready;
			c.wake_pending = false;
			schedule();
		}
		return;
	}
	if (ending_) {
		// The run is over: every wait ends at once so SIGTERM can act.
		c.wait_fd = fd;
		c.wait_seq = m.seq;
		if (m.deadline != TCS_NEVER)
			c.v = std::max(c.v, m.deadline);
		c.wake_reason = TCS_WAKE_DEADLINE;
		send_wake(c);
		return;
	}
	if (c.state == CtlState::Blocked) {
		if (c.in_block && fd == (c.wait_fd >= 0 ? c.wait_fd : c.channel.get())) {
			drop(c, "it asked to wait while already waiting");
			return;
		}
		// A thread that was asleep outside the hooks woke and waits now.
		c.side.push_back(side_wait_of(m, fd, tid, c.v, sim_ns_));
		if (missed_raised_signal(c, m))
			c.side.back().wake_reason = TCS_WAKE_RECHECK;
		child_wait_begins(c, m, &c.side.back());
		c.stats.waits++;
		hear_threads(c);
		schedule();
		return;
	}
	if (c.multithreaded() && side_wait(c, m, fd, tid)) {
		child_wait_begins(c, m, &c.side.back());
		c.stats.waits++;
		if (m.flags & TCS_BLOCK_ABSOLUTE) {
			c.stats.absolute_waits++;
			if (m.deadline <= c.side.back().requested_at)
				c.stats.reported_misses++;
		}
		if (missed_raised_signal(c, m)) {
			// (At the time its process has reached, as on_early's.)
			if (c.state == CtlState::Running && cfg_.mode == TCS_MODE_CPU)
				c.account(charge_point(c, m.cpu), cfg_.mode);
			SideWait w = c.side.back();
			c.side.pop_back();
			w.wake_reason = TCS_WAKE_RECHECK;
			answer_side(c, w);
		}
		return;
	}
	if (c.state == CtlState::Running) {
		leave_lane(c);
		// Charged up to the hook's entry (see charge_point).
		int64_t cpu = charge_point(c, m.cpu);
		c.account(cpu, cfg_.mode);
		trace_slice_end(c, "blocked", cpu);
		c.cpu_at_block = cpu;
	}
	// (Ready: the budget ran out just as it began to wait; SIGSTOP has
	// already closed its slice.)
	c.stats.waits++;
	if (m.flags & TCS_BLOCK_ABSOLUTE) {
		c.stats.absolute_waits++;
		if (m.deadline <= c.v)
			c.stats.reported_misses++; // TCS_PAGE_REPORT_MISSES
	}
	c.wait_seq = m.seq;
	c.wait_fd = fd;
	c.wait_tid = tid;
	c.wait_flags = m.flags;
	c.deadline = m.deadline;
	c.in_block = true;
	c.wait_kind = block_kind_name(m.kind);
	c.wait_requested_at = c.v;
	c.wait_absolute = (m.flags & TCS_BLOCK_ABSOLUTE) != 0;
	c.recheck = (m.flags & TCS_BLOCK_RECHECK) != 0;
	c.waits_for_child = (m.flags & TCS_BLOCK_CHILD) != 0;
	c.wants_devices = (m.flags & TCS_BLOCK_DEVICES) != 0;
	c.rechecked_at = sim_ns_;
	c.wake_pending = false;
	c.state = CtlState::Blocked;
	// Threads asleep outside the hooks: looked at each step (threads.cc).
	c.others_asleep = c.multithreaded() && proc_thread_count(c.pid) > 1 + (int)c.side.size();
	child_wait_begins(c, m, nullptr);
	if (missed_raised_signal(c, m))
		wake(c, c.v, TCS_WAKE_RECHECK);
	hear_threads(c);
	schedule();
}

// Whether c has a child that runs in real time, outside tcs: a static
// program, or one whose environment lost LD_PRELOAD, started with vfork or
// posix_spawn (it would register when its program loads). A wait for a
// child then passes in real time, as that child's time does: each step is
// a re-check. Said once per child, once it has gone unregistered for long
// enough not to be one still loading.
bool Coordinator::has_real_time_child(Controller &c)
{
	bool any = false;
	int64_t now = wall_now();
	for (const auto &o : ctls_)
		if (o->parent_id == c.id && o->outside && o->state != CtlState::Exited)
			any = true;
	for (pid_t child : proc_children(c.pid)) {
		if (std::any_of(ctls_.begin(), ctls_.end(), [child](const auto &o) { return o->pid == child; }))
			continue;
		any = true;
		auto [it, fresh] = c.unregistered_children.try_emplace(child, now);
		if (!fresh && it->second >= 0 && now - it->second > kRegistrationGrace) {
			it->second = -1; // said
			warn_once("process " + std::to_string(child) + " (" + proc_name(child, "?") + "), started by " + c.name +
				  ", runs in real time: it did not load tcs's preload (a static program, or LD_PRELOAD removed "
				  "from its environment)");
		}
	}
	return any;
}

// A wait for a child's end begins (side: a thread's, else the
// controller's own). With a child in real time, the wait's own time-out
// does not count: the child's end does, in real time, looked for at each
// step (if nothing else has a next event, virtual time passes at the speed
// of real time meanwhile). After a child ended unseen (the program looked
// for it just before, and the exit came between its look and its wait), it
// re-checks at once.
void Coordinator::child_wait_begins(Controller &c, const ::tcs_msg &m, SideWait *side)
{
	if (!(m.flags & TCS_BLOCK_CHILD))
		return;
	if (has_real_time_child(c)) {
		if (side) {
			side->flags |= TCS_BLOCK_RECHECK;
		} else {
			c.recheck = true;
			c.deadline = TCS_NEVER;
		}
	}
	if (!c.child_ended)
		return;
	c.child_ended = false;
	if (side)
		side->wake_reason = TCS_WAKE_RECHECK;
	else
		wake(c, c.v, TCS_WAKE_RECHECK);
}

void Coordinator::on_early(Controller &c, const ::tcs_msg &m, int fd)
{
	if (ending_)
		return;
	if (c.state == CtlState::Blocked && c.in_block && m.seq == c.wait_seq &&
	    fd == (c.wait_fd >= 0 ? c.wait_fd : c.channel.get())) {
		wake(c, std::max(c.v, sim_ns_), TCS_WAKE_EARLY);
		schedule();
		return;
	}
	for (size_t i = 0; i < c.side.size(); i++) {
		SideWait &w = c.side[i];
		if (w.fd != fd || w.seq != m.seq)
			continue;
		w.wake_reason = TCS_WAKE_EARLY;
		if (c.state == CtlState::Running) {
			// Ended by a thread that runs: at that thread's time now (in
			// cpu mode past the slice's start by what it has computed), so
			// that what it did is never seen as done before it was.
			if (cfg_.mode == TCS_MODE_CPU)
				c.account(charge_point(c, m.cpu), cfg_.mode);
			SideWait done = w;
			c.side.erase(c.side.begin() + (long)i);
			answer_side(c, done);
		} else if (c.state == CtlState::Blocked && wake_threads(c, std::max(c.v, sim_ns_))) {
			schedule();
		}
		return; // (Ready: answered as it resumes)
	}
	// Not waiting (yet): another thread ended the wait this seq will be,
	// or the answer crossed it. Either way it is owed nothing.
	// (One such is not counted against a flood: a thread may be woken
	// just as its wait returns without asking.)
	ChannelState &st = channel_state(c, fd);
	if (st.early_ahead == 0)
		st.unanswered = std::max(0, st.unanswered - 1);
	st.early_ahead = m.seq;
}

} // namespace tcs
