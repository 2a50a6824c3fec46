// The step protocol with peers on other hosts (step_peers.h), from both
// ends. The host's: what it hears from its agents (agents.h) acted on. An
// agent's: its coordinator schedules its controllers as usual against a
// mirror of the world; where it would step the world it answers the grant
// (with what its controllers commanded) and waits for the next.
#include "remote.h"

#include <algorithm>
#include <utility>

#include "world_steps.h"

namespace tcs {

// ---- The host's end ----

void on_step_host(Run &run)
{
	const auto events =
		run.agents.hear(*run.cfg.step_host, run.world.get(), (uint64_t)run.steps, run.sim_ns, run.cfg.step_ns);
	for (const Agents::Event &e : events) {
		switch (e.kind) {
		case Agents::Event::Joined:
			if (run.cfg.on_info)
				run.cfg.on_info("agent " + e.agent + " has joined");
			grant_now(run); // where the world is now, which it may have missed
			break;
		case Agents::Event::Left:
			if (run.cfg.on_info)
				run.cfg.on_info("agent " + e.agent + " has left");
			break;
		case Agents::Event::Programs:
			if (run.cfg.on_agent_controllers)
				run.cfg.on_agent_controllers(e.agent, e.programs);
			break;
		case Agents::Event::Refused:
			warn_once(run, e.what);
			break;
		case Agents::Event::Lost:
			return lose(run, e.what);
		}
	}
	schedule(run);
}

bool agents_answered(const Run &run)
{
	return run.agents.answered((uint64_t)run.steps);
}

// The world as it is now, to every agent: after each step, when the world
// starts, and when an agent joins (it may have missed the last). Without
// agents, none: a DDS write per step would slow the world for nobody.
void grant_now(Run &run)
{
	if (!run.cfg.step_host || !run.world || run.world_held || run.agents.empty())
		return;
	run.agents.grant(*run.cfg.step_host, *run.world, (uint64_t)run.steps, run.sim_ns);
}

void lose(Run &run, const std::string &why)
{
	run.lost = why;
	if (run.cfg.on_info)
		run.cfg.on_info(why);
	begin_end(run, EndReason::Lost);
}

// ---- An agent's end ----

void on_step_agent(Run &run)
{
	std::vector<Grant> grants;
	bool host_lost = false;
	run.cfg.step_agent->take(grants, host_lost);
	if (host_lost && run.granted)
		return lose(run, "the world's host is gone (no sign of life for " + std::to_string(kStepLeaseNs / 1000000) +
			    " ms): its controllers here are ended");
	for (Grant &g : grants) {
		// Only the next: a grant read twice (an agent joining reads the
		// last one kept) or one from before our answer is not news.
		if (run.granted && (!run.awaiting_grant || g.step <= (uint64_t)run.steps))
			continue;
		if (!run.world || g.signals.size() != run.world->value_count())
			return lose(run, "the host's grants do not fit its world (" + std::to_string(g.signals.size()) +
				    " values): the world stops");
		run.world->mirror(std::move(g.signals));
		run.sim_ns = g.sim_ns;
		run.steps = (int64_t)g.step;
		if (!run.granted) {
			// Joined late: controllers that have waited for the world
			// start where it is.
			for (auto &c : run.ctls)
				advance(*c, run.sim_ns);
			run.granted = true;
			if (run.cfg.on_info)
				run.cfg.on_info("joined the world at " + std::to_string(run.sim_ns) + " ns");
		}
		run.devices.fill_streams(run.ctls, run.sim_ns + run.cfg.step_ns, run.world.get());
		run.awaiting_grant = false;
	}
	schedule(run);
}

// All our controllers have reached the step's end: what they commanded
// in it goes to the host, and we wait for its next grant. A controller that
// ran on past the step's end (nobody else needed the core) keeps what it
// commanded later for the answers to come, as the world would apply it
// only then.
void answer_grant(Run &run)
{
	Done d;
	d.step = (uint64_t)run.steps;
	d.controllers = run.programs;
	const int64_t end = run.sim_ns + run.cfg.step_ns;
	auto answer = [&d](int64_t at, size_t i, const double *values, size_t width) {
		for (size_t k = 0; k < width; k++)
			d.commands.push_back({ at, (uint32_t)i, values[k] });
	};
	if (run.world)
		run.devices.take_due(end, *run.world, answer);
	run.cfg.step_agent->answer(d);
	run.awaiting_grant = true;
}

// Word of our controllers, before the first grant (the host may wait for
// them) and when they come or go: the list every answer then carries, made
// here rather than once a step.
void word_of_controllers(Run &run)
{
	if (!run.cfg.step_agent)
		return;
	run.programs.clear();
	for (const auto &c : run.ctls)
		if (c->parent_id == 0 && c->state() != CtlState::Exited)
			run.programs.push_back(c->name.substr(c->name.find_last_of('/') + 1));
	Done d;
	d.step = Done::kNoStep;
	d.controllers = run.programs;
	run.cfg.step_agent->answer(d);
}

} // namespace tcs
