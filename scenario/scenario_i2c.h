// The [[i2c]] tables of a scenario (DESIGN §9): I2C buses the controller
// opens as /dev/i2c-<bus>, each at its clock, with the chips on it
// ([[i2c.device]]: MPU-6050 inertial sensors, each mounted on a link).
#pragma once

#include "scenario_reader.h"

namespace tcs::scenario_parse {

// The I2C buses (after the devices and serial lines, whose paths
// /dev/i2c-<bus> must not be).
Status parse_i2cs(const toml::table &root, ScenarioReader &r);

} // namespace tcs::scenario_parse
