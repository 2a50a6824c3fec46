// An actuator on a CAN bus speaking the MIT mini-cheetah protocol
// (mit_codec.h), as T-Motor AK and CubeMars drives do: it answers every
// well-formed frame addressed to it with its state, and in motor mode
// applies τ = kp·(p_des − p) + kd·(v_des − v) + τ_ff, saturated at
// ±torque_range, p measured from the zero its FE command set.
//
// What it does where drives differ or the protocol is silent:
//  - a command is taken in or out of motor mode (and replied to), but
//    applies no torque out of it; entering motor mode (FC) clears the last
//    command (kp = kd = τ_ff = 0), so that a stale command cannot jerk the
//    joint: the torque is 0 until the first command after FC; exiting (FD)
//    clears it too;
//  - FE (zero) is taken in either mode;
//  - the reply goes out after the frame is taken: an FE's reply reports
//    position 0, an FC's the state with no torque applied yet (the
//    torque field is what the caller says it applies);
//  - a frame on its id that is not an 8-byte classic data frame with an
//    11-bit id (another length, remote, extended, FD) is ignored, with no
//    reply, as its CAN controller's filter or the firmware's length check
//    drops it; the note says why.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "can_frame.h"
#include "mit_codec.h"

namespace tcs {

class MitMotor {
public:
	// ranges: positive and finite (the scenario checks them). reply_id:
	// the CAN id the replies go to (0, the master's, by default); over
	// 0x7FF, an extended one.
	MitMotor(uint8_t id, MitRanges ranges = {}, uint32_t reply_id = 0);

	// Takes a frame seen on the bus, given the joint's position (rad, not
	// yet zeroed), velocity and the torque the motor applies now; the
	// reply, when there is one. A frame not for it: none and no note; one
	// for it that it ignores: none and *note (if note) says why.
	std::optional<CanFrame> receive(const CanFrame &frame, double position, double velocity,
					double torque_applied, std::string *note);
	// The torque the motor applies at this state (0 out of motor mode, or
	// when position or velocity is not finite).
	double torque(double position, double velocity) const;
	bool enabled() const { return enabled_; }
	uint8_t id() const { return id_; }
	// The position the motor reports for the joint's (relative to its zero).
	double position(double joint_position) const { return joint_position - zero_; }

private:
	uint8_t id_;
	MitRanges ranges_;
	uint32_t reply_id_;
	bool enabled_ = false;
	double zero_ = 0;
	MitCommand command_;
};

} // namespace tcs
