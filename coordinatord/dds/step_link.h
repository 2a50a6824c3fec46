// The step protocol (step_peers.h) carried on Cyclone DDS: the host's end
// and an agent's, on the topics of idl/tcs_step.idl. Each wakes the run's
// loop through an eventfd that DDS's listener threads write to, so the
// loop takes samples on its own thread and never waits on DDS.
//
// Loss of a peer is DDS liveliness (automatic, a 1 s lease): a peer whose
// process dies stops asserting it, its instance becomes not alive, and the
// other end's take() reports it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "error.h"
#include "step_peers.h"

namespace tcs {

struct HostedWorldInfo {
	uint32_t world = 0;   // its id on the domain
	std::string host;     // the host's name, for messages
	std::string scenario; // the scenario file's text
	int mode = 0;         // TCS_MODE_*
};

// The host's end. Create it before the coordinator takes SCHED_FIFO and
// its core (DDS's threads inherit both).
Result<std::unique_ptr<StepHost>> open_step_host(uint32_t domain, const HostedWorldInfo &world);

struct AgentJoin {
	std::unique_ptr<StepAgent> link;
	HostedWorldInfo world;
};
// An agent's end: waits up to timeout_ns for a world on the domain.
Result<AgentJoin> join_world(uint32_t domain, const std::string &agent, int64_t timeout_ns);

} // namespace tcs
