// What a CAN_RAW socket receives and its options (can_ports.cc), as the
// kernel's net/can/raw.c decides them: the CanWire's sockets, a frame at
// a time.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "can_bus.h"
#include "wire_port.h"

namespace tcs {

// The world's transmit queues (motors, sensor frames) are numbered from
// here; the sockets' below it.
constexpr uint32_t kCanWorldSources = 0x80000000u;

// CAN_RAW's socket options on port as raw_setsockopt takes them: 0, -EINVAL
// for a bad length, -ENOPROTOOPT for an unknown option.
int64_t can_set_option(WirePort &port, int32_t level, int32_t name, std::string_view value);
// Whether port's filters pass the frame.
bool can_filters_pass(const WirePort &port, const CanFrame &frame);
// The frame d, which has ended on interface ifindex, to every port that
// receives it; loopback: the sending socket's CAN_RAW_LOOPBACK when it sent.
void can_deliver(const std::vector<std::weak_ptr<WirePort>> &ports, int32_t ifindex, const CanDelivery &d,
		 bool loopback);

} // namespace tcs
