// The step protocol with peers on other hosts (step_peers.h), from both
// ends. The host's: what it hears from its agents (agents.h) acted on. An
// agent's: its coordinator schedules its controllers as usual against a
// mirror of the world; where it would step the world it answers the grant
// (with what its controllers commanded) and waits for the next.
#include <algorithm>
#include <utility>

#include "coordinator.h"

namespace tcs {

// ---- The host's end ----

void Coordinator::on_step_host()
{
	for (const Agents::Event &e : agents_.hear(*cfg_.step_host, world_.get(), (uint64_t)steps_, sim_ns_, cfg_.step_ns)) {
		switch (e.kind) {
		case Agents::Event::Joined:
			if (cfg_.on_info)
				cfg_.on_info("agent " + e.agent + " has joined");
			grant_now(); // where the world is now, which it may have missed
			break;
		case Agents::Event::Left:
			if (cfg_.on_info)
				cfg_.on_info("agent " + e.agent + " has left");
			break;
		case Agents::Event::Programs:
			if (cfg_.on_agent_controllers)
				cfg_.on_agent_controllers(e.agent, e.programs);
			break;
		case Agents::Event::Refused:
			warn_once(e.what);
			break;
		case Agents::Event::Lost:
			return lose(e.what);
		}
	}
	schedule();
}

bool Coordinator::agents_answered() const
{
	return agents_.answered((uint64_t)steps_);
}

// The world as it is now, to every agent: after each step, when the world
// starts, and when an agent joins (it may have missed the last). Without
// agents, none: a DDS write per step would slow the world for nobody.
void Coordinator::grant_now()
{
	if (!cfg_.step_host || !world_ || held_ || agents_.empty())
		return;
	agents_.grant(*cfg_.step_host, *world_, (uint64_t)steps_, sim_ns_);
}

void Coordinator::lose(const std::string &why)
{
	lost_ = why;
	if (cfg_.on_info)
		cfg_.on_info(why);
	begin_end(EndReason::Lost);
}

// ---- An agent's end ----

void Coordinator::on_step_agent()
{
	std::vector<Grant> grants;
	bool host_lost = false;
	cfg_.step_agent->take(grants, host_lost);
	if (host_lost && granted_)
		return lose("the world's host is gone (no sign of life for " + std::to_string(kStepLeaseNs / 1000000) +
			    " ms): its controllers here are ended");
	for (Grant &g : grants) {
		// Only the next: a grant read twice (an agent joining reads the
		// last one kept) or one from before our answer is not news.
		if (granted_ && (!awaiting_grant_ || g.step <= (uint64_t)steps_))
			continue;
		if (!world_ || g.signals.size() != world_->value_count())
			return lose("the host's grants do not fit its world (" + std::to_string(g.signals.size()) +
				    " values): the world stops");
		world_->mirror(std::move(g.signals));
		sim_ns_ = g.sim_ns;
		steps_ = (int64_t)g.step;
		if (!granted_) {
			// Joined late: controllers that have waited for the world
			// start where it is.
			for (auto &c : ctls_)
				c->v = std::max(c->v, sim_ns_);
			granted_ = true;
			if (cfg_.on_info)
				cfg_.on_info("joined the world at " + std::to_string(sim_ns_) + " ns");
		}
		devices_.fill_streams(ctls_, sim_ns_ + cfg_.step_ns, world_.get());
		awaiting_grant_ = false;
	}
	schedule();
}

// All our controllers have reached the step's end: what they commanded
// in it goes to the host, and we wait for its next grant. A controller that
// ran on past the step's end (nobody else needed the core) keeps what it
// commanded later for the answers to come, as the world would apply it
// only then.
void Coordinator::answer_grant()
{
	Done d;
	d.step = (uint64_t)steps_;
	d.controllers = programs_;
	const int64_t end = sim_ns_ + cfg_.step_ns;
	auto answer = [&d](int64_t at, size_t i, const double *values, size_t width) {
		for (size_t k = 0; k < width; k++)
			d.commands.push_back({ at, (uint32_t)i, values[k] });
	};
	if (world_)
		devices_.take_due(end, *world_, answer);
	cfg_.step_agent->answer(d);
	awaiting_grant_ = true;
}

// Word of our controllers, before the first grant (the host may wait for
// them) and when they come or go: the list every answer then carries, made
// here rather than once a step.
void Coordinator::word_of_controllers()
{
	if (!cfg_.step_agent)
		return;
	programs_.clear();
	for (const auto &c : ctls_)
		if (c->parent_id == 0 && c->state != CtlState::Exited)
			programs_.push_back(c->name.substr(c->name.find_last_of('/') + 1));
	Done d;
	d.step = Done::kNoStep;
	d.controllers = programs_;
	cfg_.step_agent->answer(d);
}

} // namespace tcs
