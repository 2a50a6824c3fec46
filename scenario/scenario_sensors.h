// The sensor models of a scenario: [[sensor]] tables, each noise, bias,
// quantisation, latency and a sampling rate on one signal of its models.
#pragma once

#include "scenario_reader.h"

namespace tcs::scenario_parse {

// The sensor models (after the models, whose signals they name).
Status parse_sensors(const toml::table &root, ScenarioReader &r);

} // namespace tcs::scenario_parse
