// A robot description (description.h) as a simulated model: its links as
// ODE bodies, its joints, collisions and sensors, in an ODE world of its
// own (as every built-in model has: models never touch each other, so a
// robot touches only its own links, its floor included).
//
// Signals, in this order (<name> is the instance's name):
//  - per moving joint, in the description's order (revolute, continuous,
//    prismatic, universal; fixed and ball joints have none: the child
//    link's pose and twist say where a ball joint is):
//    <name>.<joint>.position (rad or m), .velocity (rad/s or m/s),
//    .effort (N*m or N, writable: the effort held from the next step on,
//    reading what was applied, that is after saturation at the joint's
//    effort limit). A universal joint's three are 2 wide: about its
//    `axis`, then about its `axis2`.
//  - per link, in the description's order: <name>.<link>.pose (7: x y z
//    qw qx qy qz of the link's frame, not of its centre of mass, in the
//    world) and .twist (6: vx vy vz of the link frame's origin, wx wy wz,
//    both in the world frame).
//  - per sensor, in the description's order:
//    imu: .orientation (4: w x y z of the sensor frame in the world),
//         .angular_velocity (3, rad/s, sensor frame),
//         .linear_acceleration (3, m/s^2, sensor frame, what an
//         accelerometer reads: a - g, +9.81 up at rest);
//    force_torque: .force (3, N), .torque (3, N*m, about the joint's
//         anchor): what the joint exerts on its child link, constraint
//         and (hinge, slider) effort and damping, in the child's frame;
//    contact: .count (1, contact points on the link in the last step),
//         .force (3, N, world frame, their sum on the link);
//    ray: .range (1, m, along the sensor's x, range_max when nothing is
//         hit; the beam starts at range_min and does not see its own
//         link).
//  Every sensor is computed at every step; its rate (the file's
//  update_rate) goes with its signals' description, for the coordinator,
//  which samples and holds them (sensor_models.h).
//
// Joints: stops on revolute and prismatic joints (a universal joint's on
// its first axis), within -pi..pi for angles; damping as an explicit
// torque -d v; Coulomb friction as a motor held at zero velocity with at
// most `friction` (a ball joint's about each of the child's axes);
// effort_limit saturates the command; at velocity_limit the command stops
// pushing further in that direction (a motor's limit, not a stop: gravity
// may still take the joint past it).
// Links welded to the world (the model static, the root `fixed`, or
// joined to the world by fixed joints) get no body: their mass is not
// used, and they alone may carry planes. Two links collide only when both
// set self_collide and no joint joins them (Gazebo's rule).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>

#include "description.h"
#include "error.h"
#include "model.h"

namespace tcs::sim {

struct RobotOptions {
	// The root link's pose in the world (the scenario's); absent: the
	// description's model pose places the model.
	std::optional<robot::Pose> pose;
	// Weld the root link (links[0]) to the world.
	bool fixed = false;
	// By joint name, rad or m and rad/s or m/s, from the description's
	// zero (the joints of 1 degree of freedom only).
	std::map<std::string, double> initial_positions, initial_velocities;
	robot::Vec3 gravity{ 0, 0, -kGravity };
};

// Errors name what is wrong ("FILE:LINE: link 'x': ..." when the
// description knows where it came from); `name` prefixes the signals.
Result<std::unique_ptr<Model>> make_robot_model(const std::string &name, const robot::Model &desc,
						const RobotOptions &opts);

} // namespace tcs::sim
