// The [[can]] tables of a scenario (DESIGN §9): SocketCAN interfaces, each
// with its bit rates, the MIT-protocol motors on it ([[can.motor]], here)
// and its frames of signals ([[can.frame]], scenario_can_frames.h).
#pragma once

#include <cstdint>
#include <string>

#include "scenario_reader.h"

namespace tcs::scenario_parse {

// The CAN buses (after the devices: a motor must not drive an effort that
// an actuator device drives).
Status parse_cans(const toml::table &root, ScenarioReader &r);

// The CAN id at e: an integer from `least` to 0x7FF, or to 0x1FFFFFFF for
// an extended (29-bit) one, that no motor or frame of `bus` has yet (a
// standard and an extended id of the same number are two ids, as on the
// wire). `hint` follows the range in the message of one outside it.
Result<uint32_t> read_can_id(const ScenarioReader &r, const Entry &e, const CanSpec &bus, bool extended,
			     uint32_t least, const std::string &hint);

} // namespace tcs::scenario_parse
