// DxlDrive: the encoder, the loops and the motor, a step at a time (see
// dynamixel_drive.h).
#include "dynamixel_drive.h"
#include "dynamixel_motor.h"

#include <algorithm>
#include <cmath>

namespace tcs {

namespace {

// Moving Status(123) bits besides the profile's type.
constexpr uint8_t kInPositionBit = 0x01;
constexpr uint8_t kProfileOngoingBit = 0x02;
// The e-Manual names no In-Position threshold for the XM430: 10 counts
// (0.9 degrees) is ours.
constexpr double kInPosition = 10;

// 0.229 rpm in counts per ms, 214.577 rev/min^2 in counts per ms^2.
constexpr double kVelocityUnitCounts = 0.229 * 4096 / 60000;
constexpr double kAccelerationUnitCounts = 214.577 * 4096 / 3600 / 1e6;

bool position_mode(int64_t mode)
{
	return mode == kDxlPositionMode || mode == kDxlExtendedPositionMode || mode == kDxlCurrentPositionMode;
}

int64_t floor_div(int64_t a, int64_t b)
{
	return a / b - (a % b != 0 && (a < 0) != (b < 0));
}

int64_t to_int32(double v)
{
	return (int64_t)std::llround(std::clamp(v, double(INT32_MIN), double(INT32_MAX)));
}

// An integral no larger than what saturates the output.
double windup_clamp(double integral, double gain, double cap)
{
	return gain > 0 ? std::clamp(integral, -cap / gain, cap / gain) : 0.0;
}

} // namespace

int DxlDrive::direction(const DxlControlTable &t) const
{
	return (t.get(kDxlDriveMode) & 1) ? -1 : 1;
}

int64_t DxlDrive::present(const DxlControlTable &t) const
{
	return to_int32(double(raw_ - turns_ + t.get(kDxlHomingOffset)));
}

void DxlDrive::power_on(DxlControlTable &t)
{
	pos_i_ = vel_i_ = vel_cmd_ = 0;
	quiet_ms_ = 0;
	if (fresh_)
		return;
	wrap_turns(t);
	t.set(kDxlGoalPosition, present(t));
	t.set(kDxlPresentVelocity, to_int32(vel_units_));
	profile_.restart(double(present(t)));
	report(t, 0, 0);
}

void DxlDrive::wrap_turns(DxlControlTable &t)
{
	turns_ = floor_div(raw_, 4096) * 4096;
	t.set(kDxlPresentPosition, present(t));
}

void DxlDrive::torque_on(DxlControlTable &t)
{
	if (t.get(kDxlOperatingMode) == kDxlPositionMode)
		wrap_turns(t);
	pos_i_ = vel_i_ = 0;
	vel_cmd_ = vel_units_;
	quiet_ms_ = 0;
	profile_.restart(double(present(t)));
	goal_written(t);
}

void DxlDrive::mode_changed(DxlControlTable &t)
{
	t.set(kDxlProfileVelocity, 0);
	t.set(kDxlProfileAcceleration, 0);
	t.set(kDxlGoalPwm, t.get(kDxlPwmLimit));
	t.set(kDxlGoalCurrent, t.get(kDxlCurrentLimit));
	if (t.get(kDxlOperatingMode) == kDxlPositionMode)
		wrap_turns(t);
	profile_.restart(double(present(t)));
}

void DxlDrive::goal_written(DxlControlTable &t)
{
	const double goal = double(t.get(kDxlGoalPosition));
	if (t.get(kDxlDriveMode) & 4) {
		// Time-based: Profile Velocity is the whole move's time in ms,
		// Profile Acceleration the time accelerating (at most half).
		const double whole = double(t.get(kDxlProfileVelocity));
		const double ramp = std::min(double(t.get(kDxlProfileAcceleration)), whole / 2);
		const double distance = std::fabs(goal - profile_.pos);
		time_v_ = whole <= 0 ? 0 : distance / (whole - ramp);
		time_a_ = whole <= 0 || ramp <= 0 ? 0 : time_v_ / ramp;
	}
	double v_max, a_max;
	profile_limits(t, &v_max, &a_max);
	profile_.aim(goal, v_max, a_max);
}

void DxlDrive::profile_limits(const DxlControlTable &t, double *v_max, double *a_max) const
{
	if (t.get(kDxlDriveMode) & 4) {
		*v_max = time_v_;
		*a_max = time_a_;
		return;
	}
	*v_max = double(t.get(kDxlProfileVelocity)) * kVelocityUnitCounts;
	*a_max = double(t.get(kDxlProfileAcceleration)) * kAccelerationUnitCounts;
}

void DxlDrive::watchdog(DxlControlTable &t, double dt_ms)
{
	const int64_t limit = t.get(kDxlBusWatchdog);
	if (limit <= 0)
		return;
	quiet_ms_ += dt_ms;
	if (quiet_ms_ <= double(limit) * 20)
		return;
	// Stops where it is, as with no profile.
	t.set(kDxlBusWatchdog, -1);
	hold_ = present(t);
	profile_.restart(double(hold_));
	vel_cmd_ = 0;
}

double DxlDrive::position_loop(DxlControlTable &t, double dt_ms, double cap)
{
	const bool tripped = t.get(kDxlBusWatchdog) == -1;
	double v_max = 0, a_max = 0;
	if (!tripped)
		profile_limits(t, &v_max, &a_max);
	profile_.step(double(tripped ? hold_ : t.get(kDxlGoalPosition)), v_max, a_max, dt_ms);
	t.set(kDxlPositionTrajectory, to_int32(profile_.pos));
	t.set(kDxlVelocityTrajectory, to_int32(profile_.vel / kVelocityUnitCounts));

	const double kp = double(t.get(kDxlPositionPGain)) / 128;
	const double ki = double(t.get(kDxlPositionIGain)) / 65536;
	const double kd = double(t.get(kDxlPositionDGain)) / 16;
	const double ff1 = double(t.get(kDxlFeedforward1stGain)) / 4;
	const double ff2 = double(t.get(kDxlFeedforward2ndGain)) / 4;
	const double error = profile_.pos - double(present(t));
	const double error_rate = profile_.vel - vel_units_ * kVelocityUnitCounts;
	pos_i_ = windup_clamp(pos_i_ + error * dt_ms, ki, cap);
	const double out = kp * error + ki * pos_i_ + kd * error_rate + ff1 * profile_.vel / kVelocityUnitCounts +
			   ff2 * profile_.acc / kAccelerationUnitCounts;
	return std::clamp(out, -cap, cap);
}

double DxlDrive::velocity_loop(DxlControlTable &t, double dt_ms, double cap)
{
	const bool tripped = t.get(kDxlBusWatchdog) == -1;
	const double goal = tripped ? 0.0 : double(t.get(kDxlGoalVelocity));
	// Profile Acceleration in 0.229 rpm per ms.
	const double a = tripped ? 0.0 : double(t.get(kDxlProfileAcceleration)) * 214.577 / 60000 / 0.229;
	if (a > 0)
		vel_cmd_ += std::clamp(goal - vel_cmd_, -a * dt_ms, a * dt_ms);
	else
		vel_cmd_ = goal;
	t.set(kDxlVelocityTrajectory, to_int32(vel_cmd_));

	const double kp = double(t.get(kDxlVelocityPGain)) / 128;
	const double ki = double(t.get(kDxlVelocityIGain)) / 65536;
	const double error = vel_cmd_ - vel_units_;
	vel_i_ = windup_clamp(vel_i_ + error * dt_ms, ki, cap);
	return std::clamp(kp * error + ki * vel_i_, -cap, cap);
}

void DxlDrive::report(DxlControlTable &t, double volts, double amps)
{
	t.set(kDxlPresentPwm, supply_ > 0 ? to_int32(volts / supply_ * kDxlPwmFull) : 0);
	t.set(kDxlPresentCurrent, to_int32(amps / kDxlCurrentUnit));
	t.set(kDxlPresentInputVoltage, std::clamp<int64_t>(to_int32(supply_ * 10), 0, 0xFFFF));
	t.set(kDxlPresentTemperature, std::clamp<int64_t>(to_int32(temperature_), 0, 0xFF));
}

void DxlDrive::drive(DxlControlTable &t, int64_t mode, double w, double dt_ms, double *volts, double *amps)
{
	watchdog(t, dt_ms);
	const bool tripped = t.get(kDxlBusWatchdog) == -1;
	const double pwm_limit = double(t.get(kDxlPwmLimit));
	const double cap = std::min(std::fabs(double(t.get(kDxlGoalPwm))), pwm_limit);
	const double cap_volts = cap / kDxlPwmFull * supply_;
	const double amp_limit = double(t.get(kDxlCurrentLimit)) * kDxlCurrentUnit;
	const double current_cap = std::min(std::fabs(double(t.get(kDxlGoalCurrent))), double(t.get(kDxlCurrentLimit)));
	// The back-EMF's damping over the step, exact for a joint of known
	// inertia (kDxlBackEmfDamping * dt / J large: a light joint that an
	// explicit damper would throw back and forth).
	double damping = 1;
	const double x = inertia_ > 0 ? kDxlBackEmfDamping * dt_ms / 1000 / inertia_ : 0;
	if (x > 1e-12)
		damping = (1 - std::exp(-x)) / x;
	// Current modes: the current loop gives the voltage that draws it.
	bool current_driven = false;
	double wanted_amps = 0;
	switch (mode) {
	case kDxlPwmMode:
		*volts = std::clamp(tripped ? 0.0 : double(t.get(kDxlGoalPwm)), -pwm_limit, pwm_limit) / kDxlPwmFull *
			 supply_;
		break;
	case kDxlCurrentMode:
		current_driven = true;
		if (!tripped)
			wanted_amps =
				std::clamp(double(t.get(kDxlGoalCurrent)), -current_cap, current_cap) * kDxlCurrentUnit;
		break;
	case kDxlVelocityMode:
		*volts = velocity_loop(t, dt_ms, cap) / kDxlPwmFull * supply_;
		break;
	case kDxlCurrentPositionMode:
		current_driven = true;
		wanted_amps = position_loop(t, dt_ms, current_cap) * kDxlCurrentUnit;
		break;
	default:
		*volts = position_loop(t, dt_ms, cap) / kDxlPwmFull * supply_;
		break;
	}
	if (current_driven)
		*volts = std::clamp(wanted_amps * kDxlResistance + kDxlKe * w * damping, -cap_volts, cap_volts);
	*amps = std::clamp(dxl_motor_current(*volts, w, damping), -amp_limit, amp_limit);
}

double DxlDrive::step(DxlControlTable &t, double position_rad, double velocity_rad_s, double dt_s)
{
	if (!std::isfinite(position_rad) || !std::isfinite(velocity_rad_s))
		return 0;
	const double dt_ms = std::isfinite(dt_s) && dt_s > 0 ? dt_s * 1000 : 0;
	const int dir = direction(t);
	const double w = dir * velocity_rad_s; // the motor's way round
	raw_ = std::llround(std::clamp(2048 + dir * position_rad * kDxlCountsPerRad, -1e15, 1e15));
	vel_units_ = w / kDxlVelocityUnit;
	if (fresh_) {
		fresh_ = false;
		wrap_turns(t);
		t.set(kDxlGoalPosition, present(t));
		profile_.restart(double(present(t)));
	}
	t.set(kDxlPresentPosition, present(t));
	t.set(kDxlPresentVelocity, to_int32(vel_units_));
	tick_ms_ = std::fmod(tick_ms_ + dt_ms, 32768);
	t.set(kDxlRealtimeTick, int64_t(tick_ms_));

	const int64_t mode = t.get(kDxlOperatingMode);
	const bool on = t.get(kDxlTorqueEnable) == 1;
	double volts = 0, amps = 0;
	if (on)
		drive(t, mode, w, dt_ms, &volts, &amps);
	else
		pos_i_ = vel_i_ = 0;
	report(t, volts, amps);

	const int64_t here = present(t);
	const bool profiling = on && position_mode(mode) && profile_.ongoing;
	t.set(kDxlMoving, std::fabs(vel_units_) > double(t.get(kDxlMovingThreshold)) || profiling ? 1 : 0);
	uint8_t status = 0;
	if (on && position_mode(mode)) {
		const int64_t goal = t.get(kDxlBusWatchdog) == -1 ? hold_ : t.get(kDxlGoalPosition);
		status = profile_.type | (profiling ? kProfileOngoingBit : 0) |
			 (std::fabs(double(goal - here)) <= kInPosition ? kInPositionBit : 0);
	}
	t.set(kDxlMovingStatus, status);
	return dir * kDxlKt * amps;
}

} // namespace tcs
