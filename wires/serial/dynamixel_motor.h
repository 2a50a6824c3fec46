// The XM430-W350's motor and gearbox seen from the output shaft, from
// the e-Manual's specifications at 12.0 V: stall torque 4.1 N*m at 2.3 A,
// no-load speed 46 rpm. A DC motor's steady state, its inductance left
// out (its electrical time constant is far below a simulation step):
//
//   i = (V - Ke * w) / R,   torque = Kt * i
//
//   Kt = 4.1 / 2.3 N*m/A   (the stall figures: gear ratio and losses in)
//   R  = 12.0 / 2.3 ohm    (what draws the stall current at 12 V)
//   Ke = 12.0 / (46 rpm)   V*s/rad (no current at the no-load speed)
//
// So the back-EMF damps the joint with Kt * Ke / R = 0.85 N*m*s/rad. The
// gearbox's friction and the rotor's inertia are not modelled.
#pragma once

#include <numbers>

namespace tcs {

constexpr double kDxlStallTorque = 4.1;                              // N*m at 12 V
constexpr double kDxlStallCurrent = 2.3;                             // A
constexpr double kDxlNoLoadSpeed = 46.0 * 2 * std::numbers::pi / 60; // rad/s at 12 V
constexpr double kDxlRatedVolts = 12.0;

constexpr double kDxlKt = kDxlStallTorque / kDxlStallCurrent;           // N*m/A
constexpr double kDxlResistance = kDxlRatedVolts / kDxlStallCurrent;    // ohm
constexpr double kDxlKe = kDxlRatedVolts / kDxlNoLoadSpeed;             // V*s/rad
constexpr double kDxlBackEmfDamping = kDxlKt * kDxlKe / kDxlResistance; // N*m*s/rad

// Control table units.
constexpr double kDxlCurrentUnit = 2.69e-3;                                    // A (Goal/Present Current)
constexpr double kDxlVelocityUnit = 0.229 * 2 * std::numbers::pi / 60;         // rad/s (0.229 rpm)
constexpr double kDxlAccelerationUnit = 214.577 * 2 * std::numbers::pi / 3600; // rad/s^2 (214.577 rev/min^2)
constexpr double kDxlPwmFull = 885;                                            // PWM at 100 %
constexpr double kDxlCountsPerRad = 4096 / (2 * std::numbers::pi);

// The current the motor draws at `volts` turning at w rad/s (output
// shaft). The back-EMF's damping is scaled by `damping` (1: as is; see
// DynamixelServo::set_joint_inertia).
double dxl_motor_current(double volts, double w, double damping = 1);

} // namespace tcs
