// Reading and placing ODE bodies in the units and layouts the signals use.
#pragma once

#include <ode/ode.h>

namespace tcs::sim {

// x y z qw qx qy qz: the body's centre of mass and orientation, world frame.
void read_pose(dBodyID body, double out[7]);
// vx vy vz wx wy wz: linear velocity of the centre of mass and angular
// velocity, both in the world frame.
void read_twist(dBodyID body, double out[6]);
// Whether the body's position and velocities are all finite (a step that
// blew up leaves NaN behind).
bool body_finite(dBodyID body);

// Places a body rotated by `angle` about the unit axis `axis` through the
// world point `pivot`, from the reference pose it had at `ref_pos` with
// identity orientation, spinning at `rate` about the same axis.
void place_rotated(dBodyID body, const dVector3 pivot, const dVector3 axis, const dVector3 ref_pos,
		   double angle, double rate);
// Places a body at rest at `pos`, rotated by `angle` about the unit `axis`.
void place_at_rest(dBodyID body, const dVector3 pos, const dVector3 axis, double angle);

} // namespace tcs::sim
