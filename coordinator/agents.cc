// The host's end of the step protocol: see agents.h. The host counts each
// agent as one more participant in the barrier: the world steps only when
// its own controllers and every agent have reached the step's end, and
// after each step it grants the next, with every signal's values.
#include "agents.h"

#include <algorithm>
#include <cmath>

namespace tcs {

std::vector<Agents::Event> Agents::hear(StepHost &link, const SimWorld *world, uint64_t steps, int64_t sim_ns,
					int64_t step_ns)
{
	std::vector<Event> events;
	std::vector<Done> answers;
	std::vector<std::string> lost;
	link.take(answers, lost);
	for (Done &d : answers) {
		auto it = agents_.find(d.agent);
		if (d.step == Done::kLeaving) {
			if (it != agents_.end()) {
				events.push_back({ Event::Left, d.agent, "", {} });
				agents_.erase(it);
			}
			continue;
		}
		if (it == agents_.end()) {
			it = agents_.emplace(d.agent, State{}).first;
			events.push_back({ Event::Joined, d.agent, "", {} });
		}
		State &a = it->second;
		if (d.controllers != a.programs) {
			a.programs = d.controllers;
			events.push_back({ Event::Programs, d.agent, "", a.programs });
		}
		// An answer to this step: its commands take effect in order. One
		// to another step is a late joiner's to a grant it read before
		// joining: it answers the next.
		if (d.step != steps || a.answered == d.step || !world)
			continue;
		a.answered = d.step;
		for (const RemoteCommand &c : d.commands) {
			// From another host: only actuator signals, only scalar ones,
			// only finite values, at times no earlier than this step.
			bool ok = c.signal < world->signal_count() && world->signal(c.signal).width == 1 &&
				  (world->signal(c.signal).flags & TCS_SIM_SIGNAL_WRITABLE) && std::isfinite(c.value) &&
				  c.v >= sim_ns && c.v <= sim_ns + step_ns;
			// Several agents' answers interleave: kept in time order, as
			// apply() takes them from the front.
			if (ok)
				commands_.insert(std::upper_bound(commands_.begin(), commands_.end(), c,
								  [](const RemoteCommand &x, const RemoteCommand &y) {
									  return x.v < y.v;
								  }),
						 c);
			else
				events.push_back({ Event::Refused, d.agent,
						   "agent " + d.agent + " sent a command the world cannot take (signal " +
							   std::to_string(c.signal) + "): ignored",
						   {} });
		}
	}
	for (const std::string &name : lost)
		if (agents_.count(name)) {
			events.push_back({ Event::Lost, name,
					   "agent " + name + " is gone (no sign of life for " +
						   std::to_string(kStepLeaseNs / 1000000) + " ms): the world stops",
					   {} });
			break;
		}
	return events;
}

bool Agents::answered(uint64_t steps) const
{
	return std::all_of(agents_.begin(), agents_.end(), [steps](const auto &a) { return a.second.answered == steps; });
}

bool Agents::any_programs() const
{
	return std::any_of(agents_.begin(), agents_.end(), [](const auto &a) { return !a.second.programs.empty(); });
}

void Agents::apply(SimWorld &world, int64_t boundary)
{
	while (!commands_.empty() && commands_.front().v <= boundary) {
		world.write(commands_.front().signal, &commands_.front().value);
		commands_.pop_front();
	}
}

void Agents::grant(StepHost &link, const SimWorld &world, uint64_t steps, int64_t sim_ns)
{
	grant_.step = steps;
	grant_.sim_ns = sim_ns;
	world.read_all(grant_.signals);
	link.grant(grant_);
}

} // namespace tcs
