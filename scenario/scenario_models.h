// The world's part of a scenario: [sim] (the step, and a single model's
// type) and the models, as [model] parameters of [sim] model or as
// [[model]] tables.
#pragma once

#include "scenario_reader.h"

namespace tcs::scenario_parse {

// [sim], if there: the step, and [sim] model kept for parse_models.
Status parse_sim(const toml::table &root, ScenarioReader &r);
// The models (after parse_sim): at least one, named uniquely, relative
// model paths resolved against the file's folder.
Status parse_models(const toml::table &root, ScenarioReader &r);

} // namespace tcs::scenario_parse
