// The conservative step protocol with peers on other hosts (docs/DESIGN.md §7),
// as the coordinator sees it, whatever carries it (DDS: dds/step_link.h).
// One barrier per world step: the host of the world grants a step (the
// world's time and signals after it); each agent runs its controllers up to
// the step's end and answers with what they commanded; when every agent
// has answered, the host steps the world and grants the next.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tcs {

// How long a silent peer is still taken to be alive (DDS liveliness).
constexpr int64_t kStepLeaseNs = 1000000000;

struct Grant {
	uint64_t step = 0;        // steps the world has made
	int64_t sim_ns = 0;       // its time after them
	std::vector<double> signals; // every signal's values, in the world's order
};

struct RemoteCommand {
	int64_t v = 0;       // when the controller wrote it
	uint32_t signal = 0; // the actuator signal's index in the world
	double value = 0;
};

// An agent's answer to a grant (step), or, with step kNoStep, word of the
// controllers it has (when they come and go, and while it waits for its
// first grant), or, with kLeaving, that it goes.
struct Done {
	static constexpr uint64_t kNoStep = UINT64_MAX;
	static constexpr uint64_t kLeaving = UINT64_MAX - 1;
	std::string agent;
	uint64_t step = kNoStep;
	std::vector<RemoteCommand> commands;
	std::vector<std::string> controllers; // the programs it runs now
};

// The host's side: grants go out, answers and losses come in.
class StepHost {
public:
	virtual ~StepHost() = default;
	// Readable when answers or a loss may be waiting (the run's loop).
	virtual int fd() const = 0;
	virtual void grant(const Grant &g) = 0;
	// What has come: answers in order, and agents gone silent.
	virtual void take(std::vector<Done> &answers, std::vector<std::string> &lost) = 0;
};

// An agent's side.
class StepAgent {
public:
	virtual ~StepAgent() = default;
	virtual int fd() const = 0;
	virtual void answer(const Done &d) = 0;
	// Grants in order; host_lost when the host has gone silent.
	virtual void take(std::vector<Grant> &grants, bool &host_lost) = 0;
};

} // namespace tcs
