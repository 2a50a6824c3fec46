// A CAN bus's frames of signals ([[can.frame]], DESIGN §9): a frame the
// world sends at a rate, its fields the values of signals, or a frame the
// controller sends (command = true), its fields setting efforts. A field is
// a signal's value as an integer or float32 of its type at a byte of the
// payload, raw = (value - offset) / scale.
#pragma once

#include "scenario_reader.h"

namespace tcs::scenario_parse {

// One [[can.frame]] table, added to bus's frames (the efforts its fields
// set are then known to effort_driver).
Status parse_can_frame(ScenarioReader &r, const toml::table &t, CanSpec &bus);

} // namespace tcs::scenario_parse
