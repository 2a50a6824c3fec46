// One controller's open fd on a wire (docs/DESIGN.md §9): what has arrived
// for it, each piece with the virtual time it is due, and what the bus
// needs to know of the fd (a CAN socket's binding and options). The bus
// pushes arrivals; the device server puts them into the fd when due.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <utility>
#include <vector>

namespace tcs {

class WireBus;

struct CanFilter {
	uint32_t id = 0, mask = 0;
};

struct WirePort {
	int kind = 0;             // TCS_DEVICE_SERIAL, _I2C, _CAN
	WireBus *bus = nullptr;   // its bus (a CAN socket: the first, until bound)
	std::deque<std::pair<int64_t, std::string>> arrivals; // (due, bytes or one packet)
	std::string input;        // a stream's packets from the controller, not yet whole
	bool gone = false;        // its fd was closed
	std::string owner;        // the controller's program, as the trace names who sent

	// A CAN socket (can_wire.cc): as the kernel's CAN_RAW keeps them.
	int32_t ifindex = -1;     // bound to (0: every interface), -1: not bound
	std::vector<CanFilter> filters = { CanFilter{} }; // default: everything
	uint32_t err_mask = 0;
	bool loopback = true, recv_own = false, fd_frames = false, join_filters = false;
	uint32_t can_source = 0;  // its transmit queue on the bus (CanBus's source)

	// Arrivals kept for a reader that does not read (a controller is
	// untrusted: no unbounded growth). The oldest go first.
	static constexpr size_t kMaxArrivals = 65536;
	void push(int64_t due, std::string bytes)
	{
		if (gone)
			return;
		if (arrivals.size() == kMaxArrivals) {
			arrivals.pop_front();
			dropped++;
		}
		arrivals.emplace_back(due, std::move(bytes));
	}
	uint64_t dropped = 0;
};

} // namespace tcs
