// DxlProfile: the desired trajectory an X-series servo makes of a goal
// (e-Manual, "Profile Velocity(112)"): with no profile velocity a step to
// the goal; with a velocity and no acceleration a rectangular velocity
// profile; with both a trapezoidal one (triangular when the distance is too
// short to reach the velocity). It is computed online, step by step, so
// that a new goal while moving keeps the velocity continuous (the
// e-Manual's "Velocity Override"). Units: counts and milliseconds.
#pragma once

#include <cstdint>

namespace tcs {

// Moving Status(123) bits 4-5: the profile's type.
constexpr uint8_t kDxlProfileNone = 0x00;
constexpr uint8_t kDxlProfileRectangular = 0x10;
constexpr uint8_t kDxlProfileTriangular = 0x20;
constexpr uint8_t kDxlProfileTrapezoidal = 0x30;

struct DxlProfile {
	double pos = 0; // counts
	double vel = 0; // counts/ms
	double acc = 0; // counts/ms^2, of the last step
	bool ongoing = false;
	uint8_t type = kDxlProfileNone;

	// Where the trajectory starts (torque on, a mode change, a reboot).
	void restart(double at);
	// A goal written: the profile's type, from the distance left.
	void aim(double goal, double v_max, double a_max);
	// dt_ms on towards goal at no more than v_max (<= 0: a step) and
	// a_max (<= 0: at once).
	void step(double goal, double v_max, double a_max, double dt_ms);
};

} // namespace tcs
