// What an IMU on a link feels (a chip on a wire, docs/DESIGN.md §9): from
// the link's pose and twist at two steps, its specific force and angular
// rate in the link's own frame. The world's signals are the COM's pose
// (x y z qw qx qy qz) and twist (world frame); gravity is the built-in
// worlds' 9.81 m/s² down.
#pragma once

#include <cstdint>

namespace tcs {

struct LinkMotion {
	double accel[3] = { 0, 0, 0 }; // m/s², specific force: +g up at rest
	double gyro[3] = { 0, 0, 0 };  // rad/s
};

// pose and twist now, the linear velocity dt_s before (null: none yet,
// the link taken as not accelerating).
LinkMotion link_motion(const double pose[7], const double twist[6], const double *v_before, double dt_s);

} // namespace tcs
