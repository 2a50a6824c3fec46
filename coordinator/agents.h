// The host's end of the step protocol (step_peers.h): the agents taking
// part, the step each last answered, their commands not yet in force, and
// the grant that goes to them after each step. What it hears comes back as
// events, in order, for the coordinator to act on.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "sim_world.h"
#include "step_peers.h"

namespace tcs {

class Agents {
public:
	struct Event {
		enum Kind {
			Joined,   // a new agent: it needs the world as it is now
			Left,     // it said it goes
			Programs, // the programs it runs have changed (programs())
			Refused,  // it sent a command the world cannot take (`what`)
			Lost,     // it went silent: the run cannot go on
		};
		Kind kind;
		std::string agent;
		std::string what;
		std::vector<std::string> programs; // Programs: what it runs now
	};
	// Takes what the link has brought: answers to step `steps` of a world
	// at sim_ns stepping by step_ns (their commands checked and queued in
	// time order), joins, leaves and losses.
	std::vector<Event> hear(StepHost &link, const SimWorld *world, uint64_t steps, int64_t sim_ns,
				int64_t step_ns);
	bool empty() const { return agents_.empty(); }
	// Every agent has answered step `steps` (the world may step).
	bool answered(uint64_t steps) const;
	// Some agent runs controllers (the world waits on them).
	bool any_programs() const;
	// Their commands due by boundary, into the world, in time order.
	void apply(SimWorld &world, int64_t boundary);
	// The world as it is now (step `steps`, at sim_ns), to every agent.
	void grant(StepHost &link, const SimWorld &world, uint64_t steps, int64_t sim_ns);

private:
	struct State {
		uint64_t answered = Done::kNoStep;
		std::vector<std::string> programs;
	};
	std::map<std::string, State> agents_;
	std::deque<RemoteCommand> commands_; // theirs, not yet in force
	Grant grant_;                        // the last one made (its buffer reused)
};

} // namespace tcs
