// The world tcs-run uses without --world: the pendulum of docs/DESIGN.md §4,
// with its state sensor and torque actuator.
#pragma once

#include <string_view>

#include "error.h"
#include "scenario.h"

namespace tcs {

// The built-in world, parsed as any scenario file is.
Result<Scenario> default_scenario();
// Its text, parsed by default_scenario(); scenarios/pendulum.toml documents it.
std::string_view default_scenario_text();

} // namespace tcs
