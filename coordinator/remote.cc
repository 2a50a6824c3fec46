// The step protocol with peers on other hosts (step_peers.h), from both
// ends. The host counts each agent as one more participant in the barrier:
// the world steps only when its own controllers and every agent have
// reached the step's end, and after each step it grants the next, with
// every signal's values. An agent's coordinator schedules its controllers
// as usual against a mirror of the world; where it would step the world it
// answers the grant (with what its controllers commanded) and waits for
// the next.
#include <algorithm>
#include <cmath>
#include <utility>

#include "coordinator.h"

namespace tcs {

// ---- The host's end ----

void Coordinator::on_step_host()
{
	std::vector<Done> answers;
	std::vector<std::string> lost;
	cfg_.step_host->take(answers, lost);
	for (Done &d : answers) {
		auto it = agents_.find(d.agent);
		if (d.step == Done::kLeaving) {
			if (it != agents_.end() && cfg_.on_info)
				cfg_.on_info("agent " + d.agent + " has left");
			if (it != agents_.end())
				agents_.erase(it);
			continue;
		}
		if (it == agents_.end()) {
			it = agents_.emplace(d.agent, AgentState{}).first;
			if (cfg_.on_info)
				cfg_.on_info("agent " + d.agent + " has joined");
			grant_now(); // where the world is now, which it may have missed
		}
		AgentState &a = it->second;
		if (d.controllers != a.programs) {
			a.programs = d.controllers;
			if (cfg_.on_agent_controllers)
				cfg_.on_agent_controllers(d.agent, a.programs);
		}
		// An answer to this step: its commands take effect in order. One
		// to another step is a late joiner's to a grant it read before
		// joining: it answers the next.
		if (d.step != (uint64_t)steps_ || a.answered == d.step || !world_)
			continue;
		a.answered = d.step;
		for (const RemoteCommand &c : d.commands) {
			// From another host: only actuator signals, only scalar ones,
			// only finite values, at times no earlier than this step.
			bool ok = c.signal < world_->signal_count() && world_->signal(c.signal).width == 1 &&
				  (world_->signal(c.signal).flags & TCS_SIM_SIGNAL_WRITABLE) && std::isfinite(c.value) &&
				  c.v >= sim_ns_ && c.v <= sim_ns_ + cfg_.step_ns;
			// Several agents' answers interleave: kept in time order, as
			// apply_commands takes them from the front.
			if (ok)
				remote_commands_.insert(std::upper_bound(remote_commands_.begin(), remote_commands_.end(), c,
									 [](const RemoteCommand &x, const RemoteCommand &y) {
										 return x.v < y.v;
									 }),
							c);
			else
				warn_once("agent " + d.agent + " sent a command the world cannot take (signal " +
					  std::to_string(c.signal) + "): ignored");
		}
	}
	for (const std::string &name : lost)
		if (agents_.count(name))
			return lose("agent " + name + " is gone (no sign of life for " +
				    std::to_string(kStepLeaseNs / 1000000) + " ms): the world stops");
	schedule();
}

bool Coordinator::agents_answered() const
{
	return std::all_of(agents_.begin(), agents_.end(),
			   [this](const auto &a) { return a.second.answered == (uint64_t)steps_; });
}

// The world as it is now, to every agent: after each step, when the world
// starts, and when an agent joins (it may have missed the last). Without
// agents, none: a DDS write per step would slow the world for nobody.
void Coordinator::grant_now()
{
	if (!cfg_.step_host || !world_ || held_ || agents_.empty())
		return;
	grant_.step = (uint64_t)steps_;
	grant_.sim_ns = sim_ns_;
	world_->read_all(grant_.signals);
	cfg_.step_host->grant(grant_);
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
		fill_streams(sim_ns_ + cfg_.step_ns);
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
	while (!commands_.empty() && std::get<0>(commands_.front()) <= end) {
		auto &[at, dev, values] = commands_.front();
		dev->command = values;
		size_t off = 0;
		for (size_t i : dev->signals) {
			size_t width = world_->signal(i).width;
			for (size_t k = 0; k < width; k++)
				d.commands.push_back({ at, (uint32_t)i, values[off + k] });
			off += width;
		}
		commands_.pop_front();
	}
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
