// The virtual devices of a scenario: [[device]] tables, each a sensor or
// an actuator on signals of the scenario's models.
#pragma once

#include "scenario_reader.h"

namespace tcs::scenario_parse {

// The devices (after the models, whose signals they name).
Status parse_devices(const toml::table &root, ScenarioReader &r);

} // namespace tcs::scenario_parse
