// What a built-in model is to the world that holds it: a list of signals
// it describes once, reads and writes by its own (local) index, and a step.
// Each model owns its own ODE world, so models in one tcs world never touch
// each other: two pendulums side by side cannot collide, and a pendulum
// keeps the exact stepper even when a world of boxes sits beside it.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "params.h"
#include "error.h"

namespace tcs::sim {

// The gravity of every built-in model, m/s^2 along -z.
constexpr double kGravity = 9.81;

struct SignalDesc {
	std::string name; // the full name, "<model>.<joint>.position"
	uint32_t width;
	uint32_t flags; // TCS_SIM_SIGNAL_*
	const char *unit;
	double rate_hz = 0; // a sensor's own update rate (0: every step)
};

class Model {
public:
	virtual ~Model() = default;

	// Appends this model's signals in local-index order.
	virtual void describe(std::vector<SignalDesc> &out) const = 0;
	// `local` is always an index describe() produced; writes reach only
	// signals it marked writable, with finite values.
	virtual void read(uint32_t local, double *out) const = 0;
	virtual void write(uint32_t local, const double *values) = 0;
	// Advances by dt seconds with the efforts currently held.
	virtual Status step(double dt) = 0;
};

// A model type: its parameter table and how to make one from checked
// parameters. `name` prefixes its signals; make()'s errors (values that are
// valid one by one but not together) get "<type> '<name>': " added by the
// caller.
struct ModelType {
	const char *type;
	std::span<const ParamSpec> params;
	Result<std::unique_ptr<Model>> (*make)(const std::string &name, const Params &p);
};

extern const ModelType pendulum_model;
extern const ModelType cartpole_model;
extern const ModelType double_pendulum_model;
extern const ModelType boxes_model;

} // namespace tcs::sim
