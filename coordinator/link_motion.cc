// An IMU's view of a link's motion (see link_motion.h).
#include "link_motion.h"

namespace tcs {

namespace {

constexpr double kGravity = 9.81;

// v in the frame of the unit quaternion q = (w, x, y, z): q* v q.
void to_body(const double q[4], const double v[3], double out[3])
{
	const double w = q[0], x = -q[1], y = -q[2], z = -q[3]; // the conjugate rotates back
	// t = 2 (u × v), out = v + w t + u × t, u = (x, y, z)
	const double t0 = 2 * (y * v[2] - z * v[1]), t1 = 2 * (z * v[0] - x * v[2]), t2 = 2 * (x * v[1] - y * v[0]);
	out[0] = v[0] + w * t0 + (y * t2 - z * t1);
	out[1] = v[1] + w * t1 + (z * t0 - x * t2);
	out[2] = v[2] + w * t2 + (x * t1 - y * t0);
}

} // namespace

LinkMotion link_motion(const double pose[7], const double twist[6], const double *v_before, double dt_s)
{
	double f[3] = { 0, 0, kGravity };
	if (v_before && dt_s > 0)
		for (int i = 0; i < 3; i++)
			f[i] += (twist[i] - v_before[i]) / dt_s;
	LinkMotion m;
	to_body(pose + 3, f, m.accel);
	to_body(pose + 3, twist + 3, m.gyro);
	return m;
}

} // namespace tcs
