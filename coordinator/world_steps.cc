// The world's side of conservative synchronisation (docs/DESIGN.md §2). The world
// steps from S to S+dt only when every controller has reached S+dt (then it
// is held by SIGSTOP) or waits for a time at or past it. Until then the
// controllers that are behind run, one on each core tcs may use (lanes.cc),
// each with a CPU budget that ends exactly at S+dt (slices.cc). Who runs
// next and how far, or how far the world steps, is decided by decide()
// (scheduler.h); this carries it out.
#include "world_steps.h"

#include <algorithm>

#include "asleep.h"
#include "device_requests.h"
#include "remote.h"
#include "scheduler.h"
#include "slices.h"
#include "tcs/protocol.h"
#include "transitions.h"
#include "threads.h"
#include "waits.h"

namespace tcs {

namespace {
// The longest the world computes before the event loop gets a turn.
constexpr int64_t kAdvanceSlice = 20 * TCS_NS_PER_MS;
// A world step that costs more wall time than this is heavy.
constexpr int64_t kHeavyStep = 100 * TCS_NS_PER_US;
// A turn chosen this many times over with nothing changed: a defect.
constexpr int kSameTurns = 1000;
// How far behind real time an idle world may fall and catch up.
constexpr int64_t kIdleCatchUp = 50 * TCS_NS_PER_MS;
} // namespace

void schedule(Run &run)
{
	if (run.ending || run.world_held || run.awaiting_grant || !run.fatal || run.hearing_threads)
		return;
	const bool barrier = !run.agents.empty() || run.cfg.step_agent;
	// The same turn chosen again and again with nothing changed is a
	// defect of ours (a state no decision moves); rather than spin deaf
	// to the event loop (the controller's end, Ctrl-C), the loop gets its
	// turn and this decision is taken again a step's wall time later.
	size_t last_who = SIZE_MAX;
	int64_t last_at = -1, last_sim = -1;
	int same = 0;
	for (;;) {
		const int64_t target = run.sim_ns + run.cfg.step_ns;
		run.contenders.resize(run.ctls.size());
		for (size_t i = 0; i < run.ctls.size(); i++)
			run.contenders[i] = contender_of(run, *run.ctls[i]);
		const Decision d = decide(run.contenders, run.sim_ns, run.cfg.step_ns, barrier);
		switch (d.kind) {
		case Decision::Nobody: {
			// Everyone has exited: run() notices; served, the world goes
			// on at real-time speed until someone attaches, here or at an
			// agent; with controllers at an agent, at the step protocol's
			// pace (an agent answers at once: its host sets the pace).
			if (run.cfg.step_agent || run.agents.any_programs()) {
				if (!advance_to(run, target))
					return;
				continue;
			}
			if (run.cfg.serve)
				arm_idle_step(run);
			return;
		}
		case Decision::Run:
			same = d.who == last_who && d.at == last_at && run.sim_ns == last_sim ? same + 1 : 0;
			last_who = d.who, last_at = d.at, last_sim = run.sim_ns;
			if (same == kSameTurns) {
				warn_once(run, "the scheduler chose " + run.ctls[d.who]->name +
						       " again and again with nothing changed (a defect of tcs: please report it); "
						       "it looks again every step's wall time");
				run.continue_timer.arm(run.cfg.step_ns);
				return;
			}
			if (run_best(run, *run.ctls[d.who], d.at, run_until(run.contenders, d.who, target, run.cfg.duration_ns)))
				continue;
			[[fallthrough]]; // (no core for it: it waits for one of those running)
		case Decision::Wait:
			// The world steps once those running have reached it. One
			// resumed alone has no budget; if another has come since (a
			// child registered), it gets one, to where that one needs
			// the core or the world.
			for (size_t i = 0; i < run.ctls.size(); i++)
				if (run.ctls[i]->state() == CtlState::Running)
					budget_to(run, *run.ctls[i], run_until(run.contenders, i, target, run.cfg.duration_ns));
			return;
		case Decision::Idle:
			// Every controller waits for something only the real world
			// can end (some looked at each step: asleep outside the hooks,
			// or in a wait only a re-check can see end): let virtual time
			// pass at real-time speed, and hear their channels meanwhile.
			arm_idle_step(run);
			return;
		case Decision::Step:
			if (!advance_to(run, d.to))
				return;
			continue;
		}
	}
}

// The contender best is behind the step, its turn due at `at`: it takes a
// free core (the next one the next: none waits for another) and runs to
// `until`. False when every core is taken (the next to leave one goes on).
bool run_best(Run &run, Controller &best, int64_t at, int64_t until)
{
	const int lane = run.lanes.free_for(best);
	if (lane < 0)
		return false;
	// Asleep outside the hooks, with threads whose waits end now (they
	// were asleep too, in those waits): it runs again, they first; its
	// turn passing would leave it first in line at the same time for ever.
	if (best.state() == CtlState::Asleep && std::any_of(best.side_waits.begin(), best.side_waits.end(),
				       [&](const Request &w) { return best.side_due(w, at, run.sim_ns); }))
		wake_from_asleep(run, best);
	if (best.state() == CtlState::Asleep && still_asleep(run, best, at)) {
		// Looked at: still asleep, its turn passes for this step.
		looked_at(run, best, true);
		return true;
	}
	const int64_t target = run.sim_ns + run.cfg.step_ns;
	if (best.state() == CtlState::Blocked && (!best.side_waits.empty() || best.others_asleep)) {
		// Several threads wait: end those due (threads.cc).
		if (!wake_threads(run, best, at)) {
			looked_at(run, best);
			for (Request &w : best.side_waits)
				w.rechecked_at = run.sim_ns;
			return true;
		}
	} else if (best.state() == CtlState::Blocked && best.next_timer() < best.wait.deadline &&
		   raise_timers_in_read(best, at)) {
		looked_at(run, best);
		return true;
	} else if (best.state() == CtlState::Blocked && best.next_timer() <= at && best.next_timer() < best.wait.deadline) {
		// A signal timer is due in its wait: send it, and wake it to
		// re-check (its wait ends with EINTR if a handler ran).
		advance(best, at);
		looked_at(run, best);
		wake(run, best, best.v(), TCS_WAKE_SIGNAL, (int64_t)best.take_due_timer_signals());
	} else if (best.state() == CtlState::Blocked) {
		bool due = best.wait.deadline < target;
		looked_at(run, best);
		wake(run, best, due ? std::max(best.v(), best.wait.deadline) : at,
		     due || best.wait.devices ? TCS_WAKE_DEADLINE : TCS_WAKE_RECHECK);
	}
	if (best.sync && !complete_sync(run, best)) {
		// A read that must wait for its next record. Other threads'
		// waits due meanwhile end now, at their time: the reader's
		// request is the controller's own, theirs would otherwise wait
		// for it (and the scheduler would choose them again and again).
		// (What they then compute before they wait again is not charged:
		// the controller is Blocked on the read until it resumes.)
		if (std::any_of(best.side_waits.begin(), best.side_waits.end(),
				[&](const Request &w) { return best.side_due(w, best.v(), run.sim_ns); })) {
			best.publish_slice(best.cpu_at_end >= 0 ? best.cpu_at_end : best.cpu_now()); // (their clocks)
			end_side_waits(run, best);
		}
		return true;
	}
	resume(run, best, until, lane);
	return true;
}

// What the decision needs of c (scheduler.h).
Contender contender_of(const Run &run, const Controller &c)
{
	Contender k;
	k.exited = c.state() == CtlState::Exited || c.state() == CtlState::Dropped; // (dying)
	if (k.exited)
		return k;
	k.running = c.state() == CtlState::Running;
	k.at = next_run_at(run, c);
	k.rechecks = waiting(c.state()) &&
		     (c.wait.recheck || c.others_asleep || std::any_of(c.side_waits.begin(), c.side_waits.end(), [](const Request &w) {
			      return (w.flags & TCS_BLOCK_RECHECK) != 0;
		      }));
	const bool for_child = c.wait.for_child || std::any_of(c.side_waits.begin(), c.side_waits.end(), [](const Request &w) {
				       return (w.flags & TCS_BLOCK_CHILD) != 0;
			       });
	k.waits_on_running_child = waiting(c.state()) && for_child &&
				   std::any_of(run.ctls.begin(), run.ctls.end(), [&c](const auto &o) {
					   return o->parent_id == c.id && o->state() == CtlState::Running;
				   });
	return k;
}

int64_t next_run_at(const Run &run, const Controller &c)
{
	if (c.state() == CtlState::Ready || c.state() == CtlState::Running)
		return c.v();
	bool side_recheck = false, side_devices = false;
	for (const Request &w : c.side_waits) {
		side_recheck |= (w.flags & TCS_BLOCK_RECHECK) && w.rechecked_at < run.sim_ns;
		side_devices |= (w.flags & TCS_BLOCK_DEVICES) != 0;
		if (w.reason)
			return c.v();
	}
	if (((c.wait.recheck || c.others_asleep) && c.wait.rechecked_at < run.sim_ns) || side_recheck)
		return std::max(c.v(), run.sim_ns);
	int64_t until = std::min({ c.wait.deadline, c.next_timer(), c.side_next(), c.wait.signalled_at });
	// A read waiting on a wire waits for arrivals too: another
	// controller's CAN frame is put on its way after the read began, so
	// the deadline the read was given cannot know it.
	const bool wire_read = c.sync && c.sync->kind == TCS_SYNC_READ && c.sync->handle >= 0 &&
			       size_t(c.sync->handle) < c.devices.size() && c.devices[size_t(c.sync->handle)]->wire;
	if (c.wait.devices || side_devices || wire_read)
		until = std::min(until, next_record_due(c));
	return until == TCS_NEVER ? TCS_NEVER : std::max(c.v(), until);
}

bool advance_to(Run &run, int64_t next)
{
	// An agent's world is stepped by its host: answer its grant instead.
	if (run.cfg.step_agent) {
		answer_grant(run);
		return false;
	}
	// A host steps only when every agent has answered (on_step_host goes on).
	if (!agents_answered(run))
		return false;
	if (run.cfg.duration_ns >= 0 && next >= run.cfg.duration_ns)
		next = std::max(run.cfg.duration_ns, run.sim_ns);
	if (!run.world) {
		// An empty world: nothing to compute on the way.
		run.steps += (next - run.sim_ns + run.cfg.step_ns - 1) / run.cfg.step_ns;
		run.sim_ns = next;
	}
	// A heavy world (a step costing more than a budget timer's slack) is
	// computed at normal priority; see coordinator_fifo().
	bool heavy = run.world && run.world->last_step_wall_ns() > kHeavyStep && run.sim_ns < next;
	if (heavy)
		coordinator_fifo(run.rt, false);
	// At most a slice of wall time here: the rest after the event loop has
	// had its turn (a controller asleep for hours must not make tcs deaf to
	// Ctrl-C or to a controller's death while the world computes them).
	const int64_t yield_at = wall_now() + kAdvanceSlice;
	bool yielded = false;
	while (run.sim_ns < next) {
		if (auto s = step_world(run); !s) {
			run.fatal = s;
			break;
		}
		if (!agents_answered(run))
			break; // the next step waits for the agents' answers
		if (run.sim_ns < next && wall_now() >= yield_at) {
			run.continue_timer.arm(1);
			yielded = true;
			break;
		}
	}
	if (heavy)
		coordinator_fifo(run.rt, true);
	if (!run.fatal || yielded)
		return false;
	if (run.cfg.duration_ns >= 0 && run.sim_ns >= run.cfg.duration_ns) {
		begin_end(run, EndReason::Duration);
		return false;
	}
	return agents_answered(run);
}

// The next step of a world that runs at real-time speed, on a wall clock
// anchored where it began to, so that the time steps take (and this
// coordinator waiting for its core, under load) is not lost from it. Far
// behind (the machine paused), it starts again from now.
void arm_idle_step(Run &run)
{
	int64_t now = wall_now();
	if (run.sim_ns != run.idle.next_sim || now - run.idle.wall_for(run.sim_ns) > kIdleCatchUp)
		run.idle = Run::IdlePace{ now, run.sim_ns, 0 };
	run.idle.next_sim = run.sim_ns + run.cfg.step_ns;
	run.idle_timer.arm(std::max<int64_t>(run.idle.wall_for(run.idle.next_sim) - now, 1));
}

void on_idle(Run &run)
{
	run.idle_timer.consume();
	if (run.lanes.any_running() || run.ending || run.world_held)
		return;
	if (advance_to(run, run.sim_ns + run.cfg.step_ns))
		schedule(run);
}

void apply_commands(Run &run, int64_t boundary)
{
	// Ours in the order written (the last one before the boundary wins),
	// then the agents' (agents.cc checked them).
	run.devices.take_due(boundary, *run.world, [&run](int64_t, size_t i, const double *values, size_t) {
		run.world->write(i, values);
	});
	run.agents.apply(*run.world, boundary);
}

Status step_world(Run &run)
{
	if (run.world) {
		run.wires.before_step(run.sim_ns, run.cfg.step_ns, *run.world);
		apply_commands(run, run.sim_ns);
		if (auto s = run.world->step(); !s)
			return s;
		run.step_walls.add(run.world->last_step_wall_ns());
		if (run.trace.is_open()) {
			std::vector<double> &joints = run.trace_joints; // (its room kept from step to step)
			joints.clear();
			for (size_t i : run.joint_signals)
				run.world->read(i, joints);
			run.trace.step(run.sim_ns + run.cfg.step_ns, wall_now() - run.wall_start, run.world->last_step_wall_ns(),
				       joints);
		}
		if (run.cfg.on_step)
			run.cfg.on_step(run.sim_ns + run.cfg.step_ns, *run.world);
	}
	run.sim_ns += run.cfg.step_ns;
	run.steps++;
	run.devices.fill_streams(run.ctls, run.sim_ns + run.cfg.step_ns, run.world.get());
	grant_now(run);
	return Ok{};
}

} // namespace tcs
