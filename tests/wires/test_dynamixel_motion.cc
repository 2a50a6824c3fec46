// An XM430-W350's motion (wires/serial/dynamixel_drive.h, dynamixel_motor.h):
// the Present registers read from the joint, the torque of each Operating
// Mode, and the servo on a simulated joint (its inertia integrated here,
// semi-implicit Euler at 1 ms) reaching and holding a goal with the
// default gains. Expected figures are worked out from the datasheet's
// 12 V numbers: Kt = 4.1 / 2.3 N*m/A, R = 12 / 2.3 ohm, Ke = 12 V / 46 rpm.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "dynamixel_checks.h"

namespace {

using namespace dxl_checks;
using tcs::DynamixelChain;

constexpr double kPi = std::numbers::pi;
constexpr double kDt = 0.001;

struct Servo {
	DynamixelChain chain;
	Servo() { assert_true(chain.add(1).ok()); }
	tcs::DynamixelServo &s() { return chain.servo(0); }
	int64_t get(uint16_t addr) { return s().table().get(addr); }
	// A WRITE that must succeed.
	void set(uint16_t addr, int64_t v, int bytes)
	{
		const std::vector<tcs::DxlReply> r = send(chain, write_of(1, addr, le(v, bytes)));
		assert_int_equal(r.size(), 1);
		assert_int_equal(status_of(r[0]).params.at(0), 0);
	}
};

// A joint of inertia j (kg*m^2) under the servo and a load torque.
struct Joint {
	double j;
	double theta = 0, omega = 0;
	double mgl = 0; // gravity: -mgl * sin(theta), 0 hanging down
	double step(Servo &sv)
	{
		const double tau = sv.s().step(theta, omega, kDt) - mgl * std::sin(theta);
		omega += tau / j * kDt;
		theta += omega * kDt;
		return tau;
	}
};

// Powered on where the joint is, in Operating Mode `mode`, torque on,
// aimed at `goal`: Goal Velocity in Velocity Control Mode, else Goal
// Position (with Profile Velocity `profile`).
void start(Servo &sv, Joint &joint, int mode, int64_t goal, int64_t profile = 0)
{
	joint.step(sv);
	if (mode != tcs::kDxlPositionMode)
		sv.set(tcs::kDxlOperatingMode, mode, 1);
	sv.set(tcs::kDxlProfileVelocity, profile, 4);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	if (mode == tcs::kDxlVelocityMode)
		sv.set(tcs::kDxlGoalVelocity, goal, 4);
	else
		sv.set(tcs::kDxlGoalPosition, goal, 4);
}

// At goal +-2 counts, at rest, `before` ms on and for `then` ms more.
void settles_at(Servo &sv, Joint &joint, int64_t goal, int before, int then)
{
	for (int ms = 1; ms <= before + then; ms++) {
		joint.step(sv);
		if (ms >= before) {
			assert_true(std::llabs(goal - sv.get(tcs::kDxlPresentPosition)) <= 2);
			assert_true(std::fabs(joint.omega) < 0.01);
		}
	}
}

void present_registers_from_the_joint(void **)
{
	Servo sv;
	sv.s().step(0, 0, kDt);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 2048);
	sv.s().step(kPi / 2, 0, kDt);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 3072);
	sv.s().step(-kPi / 2, 1.0, kDt);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 1024);
	assert_int_equal(sv.get(tcs::kDxlPresentVelocity), 42); // 1 rad/s: 41.7 units of 0.229 rpm
	assert_int_equal(sv.get(tcs::kDxlMoving), 1);           // above Moving Threshold 10
	sv.s().step(-kPi / 2, -0.2, kDt);
	assert_int_equal(sv.get(tcs::kDxlPresentVelocity), -8);
	assert_int_equal(sv.get(tcs::kDxlMoving), 0);
	assert_int_equal(sv.get(tcs::kDxlPresentInputVoltage), 120);
	assert_int_equal(sv.get(tcs::kDxlPresentTemperature), 40);
	assert_int_equal(sv.get(tcs::kDxlPresentCurrent), 0);
}

void turns_are_counted_and_wrapped(void **)
{
	Servo sv;
	// Powered on one turn and 0.1 rad round: 6209.19, within a turn 2113.
	sv.s().step(2 * kPi + 0.1, 0, kDt);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 2113);
	assert_int_equal(sv.get(tcs::kDxlGoalPosition), 2113); // where it was switched on
	sv.s().step(4 * kPi + 0.1, 0, kDt);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 2113 + 4096);
	// Torque on in Position Control Mode: within a turn again.
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 2113);
}

void homing_offset_and_reverse(void **)
{
	Servo sv;
	sv.set(tcs::kDxlHomingOffset, 100, 4);
	sv.s().step(0, 0, kDt);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 2148);
	sv.set(tcs::kDxlHomingOffset, 0, 4);
	sv.set(tcs::kDxlDriveMode, 1, 1); // reverse
	sv.s().step(0.5, 1.0, kDt);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 1722); // 2048 - 325.95
	assert_int_equal(sv.get(tcs::kDxlPresentVelocity), -42);
	// The torque turned round too: Goal Current 100 pulls the joint back.
	sv.set(tcs::kDxlOperatingMode, 0, 1);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	sv.set(tcs::kDxlGoalCurrent, 100, 2);
	assert_float_equal(sv.s().step(0.5, 0, kDt), -0.4795217, 1e-6);
}

void current_mode_torque_is_kt_times_i(void **)
{
	Servo sv;
	sv.set(tcs::kDxlOperatingMode, 0, 1);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	sv.set(tcs::kDxlGoalCurrent, 500, 2);
	// 500 * 2.69 mA = 1.345 A; * 4.1 / 2.3 N*m/A.
	assert_float_equal(sv.s().step(0, 0, kDt), 2.3976087, 1e-6);
	assert_int_equal(sv.get(tcs::kDxlPresentCurrent), 500);
	assert_float_equal(sv.s().step(0, 1.0, kDt), 2.3976087, 1e-6); // 9.5 V: within 12
	sv.set(tcs::kDxlGoalCurrent, -500, 2);
	assert_float_equal(sv.s().step(0, 0, kDt), -2.3976087, 1e-6);
	// At 3 rad/s the back-EMF leaves (12 - 7.473 V) / R = 0.8676 A.
	sv.set(tcs::kDxlGoalCurrent, 500, 2);
	assert_float_equal(sv.s().step(0, 3.0, kDt), 1.5466011, 1e-6);
	// Above the stall current: 12 V draws 2.3 A at most, 4.1 N*m.
	sv.set(tcs::kDxlGoalCurrent, 1000, 2);
	assert_float_equal(sv.s().step(0, 0, kDt), 4.1, 1e-6);
	assert_int_equal(sv.get(tcs::kDxlPresentCurrent), 855);
	// Torque off: nothing.
	sv.set(tcs::kDxlTorqueEnable, 0, 1);
	assert_true(sv.s().step(0, 0, kDt) == 0.0);
	assert_int_equal(sv.get(tcs::kDxlPresentCurrent), 0);
}

void pwm_mode_is_the_motor_at_a_voltage(void **)
{
	Servo sv;
	sv.set(tcs::kDxlOperatingMode, 16, 1);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	sv.set(tcs::kDxlGoalPwm, 885, 2);
	assert_float_equal(sv.s().step(0, 0, kDt), 4.1, 1e-6);               // stall
	assert_float_equal(sv.s().step(0, 46 * 2 * kPi / 60, kDt), 0, 1e-9); // no-load speed
	sv.set(tcs::kDxlGoalPwm, 442, 2);
	assert_float_equal(sv.s().step(0, 0, kDt), 2.0476836, 1e-6); // 5.993 V
	assert_int_equal(sv.get(tcs::kDxlPresentPwm), 442);
}

void current_based_position_is_limited_by_goal_current(void **)
{
	Servo sv;
	sv.s().step(0, 0, kDt);
	sv.set(tcs::kDxlOperatingMode, 5, 1);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	sv.set(tcs::kDxlGoalCurrent, 200, 2);
	sv.set(tcs::kDxlGoalPosition, 3072, 4);
	// 1024 counts away: the PID asks far more than 200 * 2.69 mA.
	assert_float_equal(sv.s().step(0, 0, kDt), 0.9590435, 1e-6);
}

void position_mode_reaches_its_goal(void **)
{
	// 90 degrees on 0.01 kg*m^2. At full voltage the servo turns at no
	// more than its no-load speed (46 rpm, 4.82 rad/s): 326 ms for pi/2;
	// within 141.6 counts (885 / 6.25) the P loop takes over, with the
	// back-EMF's damping near critical (zeta = 0.85 / (2 sqrt(18.9 *
	// 0.01)) = 0.98, wn = 43 rad/s): some 0.1 s more. So: still far at
	// 300 ms, within 2 counts by 500 ms, and there to stay.
	Servo sv;
	Joint joint{ 0.01 };
	start(sv, joint, tcs::kDxlPositionMode, 3072);
	for (int ms = 1; ms <= 300; ms++)
		joint.step(sv);
	assert_true(3072 - sv.get(tcs::kDxlPresentPosition) > 50);
	settles_at(sv, joint, 3072, 200, 1000);
	assert_int_equal(sv.get(tcs::kDxlMovingStatus) & 0x01, 1); // In-Position
	assert_int_equal(sv.get(tcs::kDxlMoving), 0);
}

void holds_an_arm_against_gravity(void **)
{
	// 0.2 kg over 0.3 m, held level: 0.2943 N*m of gravity. The default
	// gains (P only) give 6.25 PWM a count: 4.1 * 6.25 / 885 = 0.02896
	// N*m a count, so it droops 10.16 counts and stays there.
	Servo sv;
	Joint joint{ 0.2 * 0.3 * 0.3 / 3 };
	joint.mgl = 0.2 * 9.81 * 0.15;
	start(sv, joint, tcs::kDxlPositionMode, 3072);
	for (int ms = 1; ms <= 3000; ms++) {
		joint.step(sv);
		if (ms >= 1000) {
			const int64_t at = sv.get(tcs::kDxlPresentPosition);
			assert_true(at == 3061 || at == 3062);
			assert_true(std::fabs(joint.omega) < 0.01);
		}
	}
}

void a_light_joint_with_its_inertia_given(void **)
{
	// 1e-4 kg*m^2: an explicit 0.85 N*m*s/rad damper at 1 ms would take
	// 8.5 times its velocity a step and throw it back and forth; told
	// the inertia, the servo damps it exactly over the step.
	Servo sv;
	Joint joint{ 1e-4 };
	sv.s().set_joint_inertia(1e-4);
	start(sv, joint, tcs::kDxlPositionMode, 3072);
	settles_at(sv, joint, 3072, 500, 500);
}

void velocity_mode_reaches_its_goal(void **)
{
	// 50 units (11.45 rpm): the PI's integral must make up the back-EMF,
	// 2.99 V (220 PWM), at 1920 / 65536 PWM per unit*ms of error.
	Servo sv;
	Joint joint{ 0.01 };
	start(sv, joint, tcs::kDxlVelocityMode, 50);
	for (int ms = 1; ms <= 2000; ms++) {
		joint.step(sv);
		if (ms >= 1000) {
			assert_true(std::llabs(50 - sv.get(tcs::kDxlPresentVelocity)) <= 1);
			assert_true(std::llabs(220 - sv.get(tcs::kDxlPresentPwm)) <= 2);
		}
	}
}

void a_rectangular_profile(void **)
{
	// Profile Velocity 100 (22.9 rpm): 1.5633 counts/ms, so 1024 counts
	// take 655 ms; at 300 ms the trajectory is at 2048 + 469.0.
	Servo sv;
	Joint joint{ 0.01 };
	start(sv, joint, tcs::kDxlPositionMode, 3072, 100);
	for (int ms = 1; ms <= 1200; ms++) {
		joint.step(sv);
		if (ms == 300) {
			assert_int_equal(sv.get(tcs::kDxlPositionTrajectory), 2517);
			assert_int_equal(sv.get(tcs::kDxlVelocityTrajectory), 100);
			assert_int_equal(sv.get(tcs::kDxlMovingStatus), 0x12); // rectangular, ongoing
			assert_int_equal(sv.get(tcs::kDxlMoving), 1);
		}
		if (ms == 650)
			assert_true(sv.get(tcs::kDxlPositionTrajectory) < 3072);
		if (ms == 660)
			assert_int_equal(sv.get(tcs::kDxlPositionTrajectory), 3072);
	}
	assert_int_equal(sv.get(tcs::kDxlMovingStatus), 0x11); // rectangular, in position
}

void trapezoidal_and_time_based_profiles(void **)
{
	// Profile Acceleration 20 (4291.5 rev/min^2): 0.004883 counts/ms^2,
	// 320 ms to reach 1.5633 counts/ms over 250 counts: for 1024 counts,
	// 320 + 335 + 320 = 975 ms. With 5, too slow to reach it: triangular.
	Servo sv;
	sv.s().step(0, 0, kDt);
	sv.set(tcs::kDxlProfileVelocity, 100, 4);
	sv.set(tcs::kDxlProfileAcceleration, 5, 4);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	sv.set(tcs::kDxlGoalPosition, 3072, 4);
	sv.s().step(0, 0, kDt);
	assert_int_equal(sv.get(tcs::kDxlMovingStatus) & 0x30, 0x20);
	sv.set(tcs::kDxlTorqueEnable, 0, 1);
	sv.set(tcs::kDxlProfileAcceleration, 20, 4);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	sv.set(tcs::kDxlGoalPosition, 3072, 4);
	for (int ms = 1; ms <= 1000; ms++) {
		sv.s().step(0, 0, kDt); // the joint held: the trajectory alone
		if (ms == 1)
			assert_int_equal(sv.get(tcs::kDxlMovingStatus) & 0x30, 0x30);
		if (ms == 500)
			assert_int_equal(sv.get(tcs::kDxlVelocityTrajectory), 100);
		if (ms == 970)
			assert_int_equal(sv.get(tcs::kDxlMovingStatus) & 0x02, 0x02); // ongoing
		if (ms == 980) {
			assert_int_equal(sv.get(tcs::kDxlMovingStatus) & 0x02, 0);
			assert_int_equal(sv.get(tcs::kDxlPositionTrajectory), 3072);
		}
	}
	// Time-based (Drive Mode bit 2): the move in 1000 ms, 200 of them
	// accelerating: 1.28 counts/ms; at 500 ms 128 + 384 counts along.
	sv.set(tcs::kDxlTorqueEnable, 0, 1);
	sv.set(tcs::kDxlDriveMode, 4, 1);
	sv.set(tcs::kDxlProfileVelocity, 1000, 4);
	sv.set(tcs::kDxlProfileAcceleration, 200, 4);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	sv.set(tcs::kDxlGoalPosition, 2048, 4);
	sv.s().step(0, 0, kDt);
	sv.set(tcs::kDxlGoalPosition, 3072, 4);
	for (int ms = 1; ms <= 1005; ms++) {
		sv.s().step(0, 0, kDt);
		if (ms == 500)
			assert_true(std::llabs(sv.get(tcs::kDxlPositionTrajectory) - 2560) <= 2);
		if (ms == 995)
			assert_int_equal(sv.get(tcs::kDxlMovingStatus) & 0x02, 0x02);
	}
	assert_int_equal(sv.get(tcs::kDxlMovingStatus) & 0x02, 0);
	assert_int_equal(sv.get(tcs::kDxlPositionTrajectory), 3072);
}

void the_bus_watchdog_stops_it(void **)
{
	Servo sv;
	Joint joint{ 0.01 };
	start(sv, joint, tcs::kDxlVelocityMode, 50);
	sv.set(tcs::kDxlBusWatchdog, 1, 1); // 20 ms
	for (int ms = 1; ms <= 100; ms++) {
		joint.step(sv);
		sv.s().heard();
	}
	assert_int_equal(sv.get(tcs::kDxlBusWatchdog), 1);
	for (int ms = 1; ms <= 21; ms++)
		joint.step(sv);
	assert_int_equal(sv.get(tcs::kDxlBusWatchdog), -1);
	assert_int_equal(sv.get(tcs::kDxlVelocityTrajectory), 0);
	// Goals are read-only now: Data Range Error.
	const std::vector<tcs::DxlReply> r = send(sv.chain, write_of(1, tcs::kDxlGoalVelocity, le(60, 4)));
	assert_int_equal(status_of(r[0]).params[0], tcs::kDxlDataRangeError);
	sv.set(tcs::kDxlBusWatchdog, 0, 1);
	sv.set(tcs::kDxlGoalVelocity, 60, 4);
}

void realtime_tick(void **)
{
	Servo sv;
	for (int ms = 0; ms < 40000; ms++)
		sv.s().step(0, 0, kDt);
	assert_int_equal(sv.get(tcs::kDxlRealtimeTick), 40000 - 32768);
}

void non_finite_input_is_no_torque(void **)
{
	Servo sv;
	sv.s().step(0, 0, kDt);
	sv.set(tcs::kDxlOperatingMode, 16, 1);
	sv.set(tcs::kDxlTorqueEnable, 1, 1);
	assert_true(sv.s().step(NAN, 0, kDt) == 0.0);
	assert_true(sv.s().step(0, INFINITY, kDt) == 0.0);
	assert_int_equal(sv.get(tcs::kDxlPresentPosition), 2048);
	assert_true(std::isfinite(sv.s().step(1e300, 0, kDt)));
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(present_registers_from_the_joint),
		cmocka_unit_test(turns_are_counted_and_wrapped),
		cmocka_unit_test(homing_offset_and_reverse),
		cmocka_unit_test(current_mode_torque_is_kt_times_i),
		cmocka_unit_test(pwm_mode_is_the_motor_at_a_voltage),
		cmocka_unit_test(current_based_position_is_limited_by_goal_current),
		cmocka_unit_test(position_mode_reaches_its_goal),
		cmocka_unit_test(holds_an_arm_against_gravity),
		cmocka_unit_test(a_light_joint_with_its_inertia_given),
		cmocka_unit_test(velocity_mode_reaches_its_goal),
		cmocka_unit_test(a_rectangular_profile),
		cmocka_unit_test(trapezoidal_and_time_based_profiles),
		cmocka_unit_test(the_bus_watchdog_stops_it),
		cmocka_unit_test(realtime_tick),
		cmocka_unit_test(non_finite_input_is_no_torque),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
