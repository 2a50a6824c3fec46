// A robot's link as ODE holds it: a body whose origin is the link's centre
// of mass (ODE requires it there) turned like the link's frame, so that the
// link frame is the body's frame shifted by a constant offset; or no body at
// all for a link welded to the world.
#pragma once

#include <string>

#include <ode/ode.h>

#include "description.h"

namespace tcs::sim::robot {

struct RobotLink {
	std::string name;
	dBodyID body = nullptr; // null: welded to the world, at `fixed_pose`
	Pose fixed_pose; // the link frame in the world, when welded
	Vec3 com{ 0, 0, 0 }; // the centre of mass in the link frame
};

// Makes the link's body in `world` (unless `anchored`) in the pose the
// description gives, moved by `model_in_world`, at rest. The mass was
// checked (check_robot).
RobotLink make_link(dWorldID world, const Link &desc, const Pose &model_in_world, bool anchored);

// The link frame in the world, now.
Pose link_pose(const RobotLink &l);
// The velocity of the material point of the link now at `p` (world).
Vec3 point_velocity(const RobotLink &l, const Vec3 &p);
Vec3 angular_velocity(const RobotLink &l);

// The pose and twist signals (ode_robot.h says their layout).
void read_link_pose(const RobotLink &l, double out[7]);
void read_link_twist(const RobotLink &l, double out[6]);

} // namespace tcs::sim::robot
