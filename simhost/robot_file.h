// A scenario's robot file (DESIGN §8) as models of a world: the file loaded
// (sdf_load.h), each of its models placed by the scenario's parameters and
// built in ODE (ode_robot.h). The scenario carries the placement as numeric
// parameters (scenario_models.cc): fixed, pose.x ... pose.yaw,
// initial_position.<joint>, initial_velocity.<joint>.
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "error.h"
#include "model.h"
#include "tcs/simhost.h"

namespace tcs::sim {

// Whether a model type names a robot file rather than a built-in model.
bool is_robot_file(std::string_view type);

struct RobotFileModels {
	std::vector<std::unique_ptr<Model>> models;
	int64_t step_ns = 0; // an SDF world's max_step_size (0: none)
};

// The file's models, named <name>.<part>... A file error is the file's own
// "FILE:LINE: what" (the caller adds nothing); a parameter's names it.
Result<RobotFileModels> make_robot_file_models(const struct tcs_sim_model &spec);

} // namespace tcs::sim
