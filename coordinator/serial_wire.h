// A serial line as the coordinator drives it (docs/DESIGN.md §9): the
// bytes a controller writes travel to the servos at the line's rate, a
// Protocol 2.0 parser takes packets from them as they arrive, the chain of
// Dynamixel servos answers after its Return Delay Time, and the answer's
// bytes reach the controller's fd one by one at their times. Each step
// the servos' loops run on their joints.
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "dynamixel2_parser.h"
#include "dynamixel_chain.h"
#include "error.h"
#include "scenario.h"
#include "serial_line.h"
#include "wire_bus.h"

namespace tcs {

class SerialWire final : public WireBus {
public:
	static Result<std::unique_ptr<SerialWire>> create(const SerialSpec &spec, const std::string &scenario_file,
							  const SimWorld *world, Warn warn);
	int socket_type() const override;
	void opened(const std::shared_ptr<WirePort> &port) override;
	int64_t take(WirePort &port, uint32_t type, std::string_view payload, int64_t v, const SimWorld *world) override;
	int64_t next_event() const override;
	void advance(int64_t t, const SimWorld *world) override;
	void step(int64_t s, const SimWorld &world) override;
	void apply(SimWorld &world) override;
	int64_t drained_at(const WirePort &port) const override;
	void trace_topics(std::vector<TraceWireTopic> &out) const override;

private:
	SerialWire(const SerialSpec &spec, Warn warn);
	void answer(std::vector<DxlReply> replies, int64_t end);
	void note(const std::string &what);

	struct Joint {
		size_t position = 0, velocity = 0, effort = 0; // world signals
		double torque = 0;                             // this step's
	};
	SerialSpec spec_;
	Warn warn_;
	int64_t step_ns_ = 0;
	int64_t ctl_baud_;                  // the controller's tty's rate
	SerialDirection to_servos_, to_controller_;
	std::deque<uint8_t> in_flight_;     // to_servos_' bytes, in order
	Dxl2Parser parser_;
	DynamixelChain chain_;
	std::vector<Joint> joints_;         // one a servo, in chain order
	std::vector<std::weak_ptr<WirePort>> ports_;
	uint64_t notes_ = 0;
};

} // namespace tcs
