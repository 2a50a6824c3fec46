// A wire as the coordinator drives it (docs/DESIGN.md §9): one serial line,
// I2C bus or CAN interface, with the models on it (wires/), run in virtual
// time. The controllers' packets come in through take(); what the devices
// answer goes out to the ports as arrivals with their due times; the
// devices on it that move joints compute their efforts once a step.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sim_world.h"
#include "trace.h"
#include "tcs/clock_page.h"
#include "tcs/protocol.h"
#include "tcs/wire_protocol.h"
#include "wire_port.h"

namespace tcs {

class WireBus {
public:
	using Warn = std::function<void(const std::string &)>;
	virtual ~WireBus() = default;
	// SOCK_STREAM (a serial line's bytes) or SOCK_SEQPACKET.
	virtual int socket_type() const = 0;
	// A new fd on it.
	virtual void opened(const std::shared_ptr<WirePort> &port) = 0;
	// One packet the controller wrote on port, at virtual time v (the
	// world at v's step): 0 or -errno for the write.
	virtual int64_t take(WirePort &port, uint32_t type, std::string_view payload, int64_t v,
			     const SimWorld *world) = 0;
	// When the next thing happens on it by itself (TCS_NEVER: nothing).
	virtual int64_t next_event() const = 0;
	// Everything that happens up to t, the world at t's step.
	virtual void advance(int64_t t, const SimWorld *world) = 0;
	// Once a step, at its start s, before anything of that step happens
	// on the wire: the devices' loops run and their efforts are set.
	virtual void step(int64_t s, const SimWorld &world) {}
	// The efforts of step() into the world, before it steps.
	virtual void apply(SimWorld &world) {}
	// When what port wrote has all left on the wire (tcdrain).
	virtual int64_t drained_at(const WirePort &port) const { return 0; }

	// Its trace topics (a CAN bus: one an interface), in the order its
	// messages name them.
	virtual void trace_topics(std::vector<TraceWireTopic> &out) const = 0;
	// What goes over it from now on is written to trace, its topics
	// numbered from first.
	void trace_to(Trace *trace, size_t first)
	{
		trace_ = trace;
		topic_ = first;
	}

protected:
	Trace *trace_ = nullptr; // none: not traced
	size_t topic_ = 0;
};

// A trace topic's name for a device path: "/dev/ttyUSB0" -> "dev/ttyUSB0".
inline std::string wire_topic_name(const std::string &path)
{
	return path.size() > 1 && path[0] == '/' ? path.substr(1) : path;
}

} // namespace tcs
