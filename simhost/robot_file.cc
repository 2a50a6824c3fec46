// Robot files as models (see robot_file.h).
#include "robot_file.h"

#include <cmath>
#include <string>

#include "robot/ode_robot.h"
#include "robot/sdf_load.h"
#include "robot/world_merge.h"

namespace tcs::sim {

namespace {

bool ends_with(std::string_view s, std::string_view tail)
{
	return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

// x y z roll pitch yaw (rad, fixed axes x then y then z) as a pose.
robot::Pose pose_of(const double v[6])
{
	const double cr = std::cos(v[3] / 2), sr = std::sin(v[3] / 2);
	const double cp = std::cos(v[4] / 2), sp = std::sin(v[4] / 2);
	const double cy = std::cos(v[5] / 2), sy = std::sin(v[5] / 2);
	robot::Pose p;
	p.p = { v[0], v[1], v[2] };
	p.q = { cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
		cr * cp * sy - sr * sp * cy };
	return p;
}

// The scenario's parameters as options. Joint names are checked against
// the model by make_robot_model.
Result<RobotOptions> options_of(const struct tcs_sim_model &spec, const std::string &who)
{
	static const char *const kPose[] = { "pose.x", "pose.y", "pose.z", "pose.roll", "pose.pitch", "pose.yaw" };
	RobotOptions o;
	double pose[6] = { 0, 0, 0, 0, 0, 0 };
	bool posed = false;
	for (size_t i = 0; i < spec.nparams; i++) {
		const std::string key = spec.param_keys[i] ? spec.param_keys[i] : "";
		const double v = spec.param_values[i];
		if (!std::isfinite(v))
			return Error{ who + ": parameter '" + key + "' must be a finite number" };
		bool known = false;
		for (int k = 0; k < 6; k++)
			if (key == kPose[k]) {
				pose[k] = v;
				posed = known = true;
			}
		if (known)
			continue;
		if (key == "fixed")
			o.fixed = v != 0;
		else if (key.rfind("initial_position.", 0) == 0)
			o.initial_positions[key.substr(17)] = v;
		else if (key.rfind("initial_velocity.", 0) == 0)
			o.initial_velocities[key.substr(17)] = v;
		else
			return Error{ who + ": unknown parameter '" + key +
				      "' (a robot file takes fixed, pose, initial_positions, initial_velocities)" };
	}
	if (posed)
		o.pose = pose_of(pose);
	return o;
}

} // namespace

bool is_robot_file(std::string_view type)
{
	return type.find('/') != std::string_view::npos || ends_with(type, ".urdf") || ends_with(type, ".sdf") ||
	       ends_with(type, ".world");
}

Result<RobotFileModels> make_robot_file_models(const struct tcs_sim_model &spec)
{
	const std::string who = std::string(spec.type) + " '" + spec.name + "'";
	auto desc = robot::load_robot_file(spec.type);
	if (!desc)
		return desc.error();
	auto opts = options_of(spec, who);
	if (!opts)
		return opts.error();
	if (desc->gravity)
		opts->gravity = *desc->gravity;
	RobotFileModels out;
	if (desc->max_step_s && *desc->max_step_s > 0 && *desc->max_step_s <= 1)
		out.step_ns = std::llround(*desc->max_step_s * 1e9);
	const robot::Model *model = &desc->models.front();
	robot::Model merged;
	if (desc->models.size() > 1) {
		// A world's models, in one ODE world: <name>.<model>.<joint>...
		if (opts->fixed || opts->pose)
			return Error{ who + ": 'fixed' and 'pose' place a file's one model; this world has " +
				      std::to_string(desc->models.size()) + " (each placed by the file)" };
		merged = robot::merge_world(*desc);
		model = &merged;
	}
	auto made = make_robot_model(spec.name, *model, *opts);
	if (!made)
		return made.error();
	out.models.push_back(std::move(*made));
	return out;
}

} // namespace tcs::sim
