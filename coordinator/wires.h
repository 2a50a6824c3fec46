// The run's wires (docs/DESIGN.md §9): every serial line, I2C bus and CAN
// interface of the scenario, each a WireBus, in the order of their entries
// in the device table; the CAN interfaces are one WireBus, the last. What a controller writes on a wire's fd is read
// here, packet by packet, and handed to its bus; the buses advance in
// virtual time with the world (wire_bus.h says when).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "error.h"
#include "scenario.h"
#include "sim_world.h"
#include "wire_bus.h"
#include "wire_port.h"

namespace tcs {

struct WiresConfig {
	std::vector<SerialSpec> serials;
	std::vector<I2cSpec> i2cs;
	std::vector<CanSpec> cans;
	std::string scenario_file; // for FILE:LINE in errors
	uint64_t noise_key = 1;    // the chips' noise streams derive from it (the run's sensor key)
};

class Wires {
public:
	Status bind(const WiresConfig &cfg, const SimWorld *world, WireBus::Warn warn);
	bool empty() const { return buses_.empty(); }
	// The bus of the wire devices' index-th entry (its order in the table).
	WireBus *bus(size_t index) const { return index < buses_.size() ? buses_[index].get() : nullptr; }
	// A new fd on bus index.
	std::shared_ptr<WirePort> open(size_t index);
	// Everything the controller wrote on port's fd (our end sock), at
	// virtual time v: 0, or the first -errno.
	int64_t take(WirePort &port, int sock, int64_t v, const SimWorld *world);
	// Everything up to t on every wire, the world at step s (t's).
	void advance(int64_t t, int64_t s, const SimWorld *world);
	int64_t next_event() const;
	// Before the world steps from s: the devices' efforts into it.
	void before_step(int64_t s, int64_t step_ns, SimWorld &world);
	// Every wire's trace topics, in order; then what goes over each is
	// written to trace (opened with them).
	std::vector<TraceWireTopic> trace_topics() const;
	void trace_to(Trace &trace);

private:
	void step_once(int64_t s, const SimWorld *world);
	std::vector<std::unique_ptr<WireBus>> buses_;
	int64_t stepped_for_ = -1; // the step whose device loops have run
};

} // namespace tcs
