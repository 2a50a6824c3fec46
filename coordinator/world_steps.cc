// The world's side of conservative synchronisation (docs/DESIGN.md §2). The world
// steps from S to S+dt only when every controller has reached S+dt (then it
// is held by SIGSTOP) or waits for a time at or past it. Until then the
// controllers that are behind run, one on each core tcs may use (lanes.cc),
// each with a CPU budget that ends exactly at S+dt (slices.cc). Who runs
// next and how far, or how far the world steps, is decided by decide()
// (scheduler.h); this carries it out.
#include <algorithm>

#include "coordinator.h"
#include "scheduler.h"
#include "tcs/protocol.h"

namespace tcs {

namespace {
// The longest the world computes before the event loop gets a turn.
constexpr int64_t kAdvanceSlice = 20 * TCS_NS_PER_MS;
// A world step that costs more wall time than this is heavy.
constexpr int64_t kHeavyStep = 100 * TCS_NS_PER_US;
// How far behind real time an idle world may fall and catch up.
constexpr int64_t kIdleCatchUp = 50 * TCS_NS_PER_MS;
} // namespace

void Coordinator::schedule()
{
	if (ending_ || held_ || awaiting_grant_ || !fatal_ || hearing_)
		return;
	const bool barrier = !agents_.empty() || cfg_.step_agent;
	for (;;) {
		const int64_t target = sim_ns_ + cfg_.step_ns;
		contenders_.resize(ctls_.size());
		for (size_t i = 0; i < ctls_.size(); i++)
			contenders_[i] = contender_of(*ctls_[i]);
		const Decision d = decide(contenders_, sim_ns_, cfg_.step_ns, barrier);
		switch (d.kind) {
		case Decision::Nobody: {
			// Everyone has exited: run() notices; served, the world goes
			// on at real-time speed until someone attaches, here or at an
			// agent; with controllers at an agent, at the step protocol's
			// pace (an agent answers at once: its host sets the pace).
			if (cfg_.step_agent || agents_.any_programs()) {
				if (!advance_to(target))
					return;
				continue;
			}
			if (cfg_.serve)
				arm_idle_step();
			return;
		}
		case Decision::Run:
			if (!run_best(*ctls_[d.who], d.at, run_until(contenders_, d.who, target, cfg_.duration_ns)))
				return;
			continue;
		case Decision::Wait:
			return; // the world steps once those running have reached it
		case Decision::Idle:
			// Every controller waits for something only the real world
			// can end (some looked at each step: asleep outside the hooks,
			// or in a wait only a re-check can see end): let virtual time
			// pass at real-time speed, and hear their channels meanwhile.
			arm_idle_step();
			return;
		case Decision::Step:
			if (!advance_to(d.to))
				return;
			continue;
		}
	}
}

// The contender best is behind the step, its turn due at `at`: it takes a
// free core (the next one the next: none waits for another) and runs to
// `until`. False when every core is taken (the next to leave one goes on).
bool Coordinator::run_best(Controller &best, int64_t at, int64_t until)
{
	const int lane = lanes_.free_for(best);
	if (lane < 0)
		return false;
	if (best.asleep && still_asleep(best, at)) {
		// Looked at: still asleep, its turn passes for this step.
		best.wait.rechecked_at = sim_ns_;
		best.wait.kicked_at = TCS_NEVER;
		return true;
	}
	const int64_t target = sim_ns_ + cfg_.step_ns;
	if (best.state == CtlState::Blocked && (!best.side.empty() || best.others_asleep)) {
		// Several threads wait: end those due (threads.cc).
		if (!wake_threads(best, at)) {
			best.wait.rechecked_at = sim_ns_;
			for (SideWait &w : best.side)
				w.rechecked_at = sim_ns_;
			return true;
		}
	} else if (best.state == CtlState::Blocked && best.next_timer() <= at && best.next_timer() < best.wait.deadline) {
		// A signal timer is due in its wait: send it, and wake it to
		// re-check (its wait ends with EINTR if a handler ran).
		best.v = std::max(best.v, at);
		best.wake_arg = (int64_t)best.take_due_timer_signals();
		best.wait.rechecked_at = sim_ns_;
		wake(best, best.v, TCS_WAKE_SIGNAL);
	} else if (best.state == CtlState::Blocked) {
		bool due = best.wait.deadline < target;
		best.wait.rechecked_at = sim_ns_;
		wake(best, due ? std::max(best.v, best.wait.deadline) : at,
		     due || best.wait.devices ? TCS_WAKE_DEADLINE : TCS_WAKE_RECHECK);
	}
	if (best.sync_pending && !complete_sync(best))
		return true; // a read that must wait for its next record
	resume(best, until, lane);
	return true;
}

// What the decision needs of c (scheduler.h).
Contender Coordinator::contender_of(const Controller &c) const
{
	Contender k;
	k.exited = c.state == CtlState::Exited;
	if (k.exited)
		return k;
	k.running = c.state == CtlState::Running;
	k.at = next_run_at(c);
	k.rechecks = c.state == CtlState::Blocked &&
		     (c.wait.recheck || c.others_asleep || std::any_of(c.side.begin(), c.side.end(), [](const SideWait &w) {
			      return (w.flags & TCS_BLOCK_RECHECK) != 0;
		      }));
	const bool for_child = c.wait.for_child || std::any_of(c.side.begin(), c.side.end(), [](const SideWait &w) {
				       return (w.flags & TCS_BLOCK_CHILD) != 0;
			       });
	k.waits_on_running_child = c.state == CtlState::Blocked && for_child &&
				   std::any_of(ctls_.begin(), ctls_.end(), [&c](const auto &o) {
					   return o->parent_id == c.id && o->state == CtlState::Running;
				   });
	return k;
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
	if (((c.wait.recheck || c.others_asleep) && c.wait.rechecked_at < sim_ns_) || side_recheck)
		return std::max(c.v, sim_ns_);
	int64_t until = std::min({ c.wait.deadline, c.next_timer(), c.side_next(), c.wait.kicked_at });
	if (c.wait.devices || side_devices)
		until = std::min(until, next_record_due(c));
	return until == TCS_NEVER ? TCS_NEVER : std::max(c.v, until);
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
	if (lanes_.any_running() || ending_ || held_)
		return;
	if (advance_to(sim_ns_ + cfg_.step_ns))
		schedule();
}

void Coordinator::apply_commands(int64_t boundary)
{
	// Ours in the order written (the last one before the boundary wins),
	// then the agents' (agents.cc checked them).
	devices_.take_due(boundary, *world_, [this](int64_t, size_t i, const double *values, size_t) {
		world_->write(i, values);
	});
	agents_.apply(*world_, boundary);
}

Status Coordinator::step_world()
{
	if (world_) {
		apply_commands(sim_ns_);
		if (auto s = world_->step(); !s)
			return s;
		step_walls_.add(world_->last_step_wall_ns());
		if (trace_.is_open()) {
			std::vector<double> joints;
			joints.reserve(joint_signals_.size());
			for (size_t i : joint_signals_)
				world_->read(i, joints);
			trace_.step(sim_ns_ + cfg_.step_ns, wall_now() - wall_start_, world_->last_step_wall_ns(),
				    std::move(joints));
		}
		if (cfg_.on_step)
			cfg_.on_step(sim_ns_ + cfg_.step_ns, *world_);
	}
	sim_ns_ += cfg_.step_ns;
	steps_++;
	devices_.fill_streams(ctls_, sim_ns_ + cfg_.step_ns, world_.get());
	grant_now();
	return Ok{};
}

} // namespace tcs
