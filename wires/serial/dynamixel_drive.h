// DxlDrive: what an X-series servo does between packets, step by step: its
// encoder read into the Present registers, and the loop of its Operating
// Mode driving the motor (dynamixel_motor.h) from the Goal registers.
//
// The loops, with the e-Manual's gain scalings (KPP = P/128, KPI =
// I/65536, KPD = D/16; KVP = P/128, KVI = I/65536; feedforward gains /4).
// Integrals and derivatives are taken per millisecond, and errors are in
// the table's units (position: counts; velocity: 0.229 rpm):
//   Position, Extended Position: a PID on the profile's trajectory whose
//     output is PWM (885 = 100 % of the supply), plus feedforward of the
//     trajectory's velocity and acceleration;
//   Current-based Position: the same PID, its output a current in 2.69 mA
//     units, limited by Goal Current;
//   Velocity: a PI on the velocity trajectory (Profile Acceleration ramps
//     it to Goal Velocity), output PWM;
//   Current: Goal Current, held by an ideal current loop;
//   PWM: Goal PWM.
// The voltage is limited by Goal PWM (and PWM Limit), the current by
// Current Limit; the integrators stop at the output limit (anti-windup).
// With Torque Enable 0 the motor is left open: no torque, no braking.
// Choosing an Operating Mode resets what the e-Manual lists (Profile
// Velocity and Acceleration to 0, Goal PWM and Current to their limits);
// the gains stay as they are. Moving Status's In-Position bit is set
// within 10 counts of the goal (the XM430 has no threshold item; ours).
//
// Present Position is 2048 + the joint's angle * 4096 / 2pi, rounded, plus
// Homing Offset; it is put within one turn (0-4095) at power-on, at a
// REBOOT, when torque is turned on in Position Control Mode and when that
// mode is chosen. Drive Mode bit 0 (reverse) turns every direction round:
// positions, velocities, currents and the torque. Not modelled: hardware
// errors and shutdown, the temperature's rise (Present Temperature stays
// as set), the gearbox's backlash and friction.
#pragma once

#include <cmath>
#include <cstdint>

#include "dynamixel_control_table.h"
#include "dynamixel_profile.h"

namespace tcs {

class DxlDrive {
public:
	// Reads the joint (rad, rad/s) into the table's Present registers, runs
	// the loop for dt_s and returns the torque on the joint (N*m).
	double step(DxlControlTable &t, double position_rad, double velocity_rad_s, double dt_s);

	// REBOOT and FACTORY_RESET (the table just reset): Present Position
	// within one turn and Goal Position where the joint is, now if a step
	// has read the joint, else at the first step (power-on).
	void power_on(DxlControlTable &t);
	// Present Position back within one turn.
	void wrap_turns(DxlControlTable &t);
	// Torque Enable turned to 1: the loops start from where the joint is.
	void torque_on(DxlControlTable &t);
	// Operating Mode changed: what the e-Manual says is reset with it.
	void mode_changed(DxlControlTable &t);
	// Goal Position written: the profile's new leg.
	void goal_written(DxlControlTable &t);
	// An instruction packet heard: the Bus Watchdog counts from 0 again.
	void heard() { quiet_ms_ = 0; }

	// Settings from the caller: a figure not finite, or below 0, is 0.
	void set_supply(double volts) { supply_ = sane(volts); }
	void set_temperature(double celsius) { temperature_ = sane(celsius); }
	void set_joint_inertia(double kg_m2) { inertia_ = sane(kg_m2); }
	double supply() const { return supply_; }

private:
	static double sane(double v) { return std::isfinite(v) && v > 0 ? v : 0; }
	int direction(const DxlControlTable &t) const;
	int64_t present(const DxlControlTable &t) const;
	// The profile's limits in counts/ms and counts/ms^2.
	void profile_limits(const DxlControlTable &t, double *v_max, double *a_max) const;
	double position_loop(DxlControlTable &t, double dt_ms, double cap);
	double velocity_loop(DxlControlTable &t, double dt_ms, double cap);
	void watchdog(DxlControlTable &t, double dt_ms);
	// Torque on: the mode's loop, the voltage it puts on the motor and the
	// current drawn (the motor turning at w rad/s).
	void drive(DxlControlTable &t, int64_t mode, double w, double dt_ms, double *volts, double *amps);
	void report(DxlControlTable &t, double volts, double amps);

	bool fresh_ = true;    // no step has read the joint yet
	int64_t raw_ = 2048;   // encoder counts, all turns, direction applied
	int64_t turns_ = 0;    // counts taken off raw_ (a multiple of 4096)
	double vel_units_ = 0; // 0.229 rpm, direction applied
	DxlProfile profile_;
	double time_v_ = 0, time_a_ = 0; // a time-based profile's limits
	double vel_cmd_ = 0;             // velocity mode's trajectory (0.229 rpm)
	double pos_i_ = 0, vel_i_ = 0;   // the integrals
	double tick_ms_ = 0;
	double quiet_ms_ = 0;
	int64_t hold_ = 0; // where a tripped watchdog holds
	double supply_ = 12.0, temperature_ = 40.0, inertia_ = 0;
};

} // namespace tcs
