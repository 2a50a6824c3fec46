// The [[serial]] tables of a scenario (DESIGN §9): serial lines the
// controller opens by path, each at its baud rate, with the Dynamixel
// Protocol 2.0 servos on it ([[serial.servo]]).
#pragma once

#include "scenario_reader.h"

namespace tcs::scenario_parse {

// The serial lines (after the devices, whose paths theirs must not take,
// and the CAN buses, whose motors drive efforts too).
Status parse_serials(const toml::table &root, ScenarioReader &r);

} // namespace tcs::scenario_parse
