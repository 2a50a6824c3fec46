// DxlProfile: the online velocity profile (see dynamixel_profile.h).
#include "dynamixel_profile.h"

#include <algorithm>
#include <cmath>

namespace tcs {

void DxlProfile::restart(double at)
{
	pos = at;
	vel = acc = 0;
	ongoing = false;
}

void DxlProfile::aim(double goal, double v_max, double a_max)
{
	const double distance = std::fabs(goal - pos);
	if (v_max <= 0)
		type = kDxlProfileNone;
	else if (a_max <= 0)
		type = kDxlProfileRectangular;
	else
		// Accelerating to v_max and back takes v_max^2 / a_max.
		type = distance < v_max * v_max / a_max ? kDxlProfileTriangular : kDxlProfileTrapezoidal;
}

void DxlProfile::step(double goal, double v_max, double a_max, double dt_ms)
{
	if (v_max <= 0) {
		restart(goal);
		return;
	}
	const double left = goal - pos;
	if (dt_ms <= 0 || (left == 0 && vel == 0)) {
		acc = 0;
		ongoing = left != 0;
		return;
	}
	const double before = vel;
	const double sign = left >= 0 ? 1 : -1;
	if (a_max > 0) {
		// As fast as still lets it stop at the goal, a_max * dt_ms less a
		// step: from n such steps it covers a_max * dt^2 * n (n + 1) / 2.
		const double step_v = a_max * dt_ms;
		const double braking = step_v * (std::sqrt(0.25 + 2 * std::fabs(left) / (step_v * dt_ms)) - 0.5);
		const double target = sign * std::min(v_max, braking);
		vel += std::clamp(target - vel, -a_max * dt_ms, a_max * dt_ms);
	} else {
		vel = sign * v_max;
	}
	const double move = vel * dt_ms;
	if (vel * sign > 0 && move * sign >= std::fabs(left)) {
		// Arrives within this step.
		pos = goal;
		vel = 0;
		ongoing = false;
	} else {
		pos += move;
		ongoing = true;
	}
	acc = (vel - before) / dt_ms;
}

} // namespace tcs
