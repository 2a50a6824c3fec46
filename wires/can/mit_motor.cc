// MitMotor: the actuator's state machine and torque law (see mit_motor.h).
#include "mit_motor.h"

#include <cmath>
#include <string>

namespace tcs {

namespace {

// Why a frame on the motor's id is not taken; empty when it is.
std::string refusal(const CanFrame &f)
{
	if (f.extended)
		return "an extended (29-bit) frame";
	if (f.fd)
		return "a CAN FD frame (the motor speaks classic CAN)";
	if (f.rtr)
		return "a remote frame";
	if (f.len != 8)
		return "a frame of " + std::to_string(f.len) + " bytes, not 8";
	return {};
}

} // namespace

MitMotor::MitMotor(uint8_t id, MitRanges ranges, uint32_t reply_id) : id_(id), ranges_(ranges), reply_id_(reply_id)
{
}

std::optional<CanFrame> MitMotor::receive(const CanFrame &frame, double position, double velocity,
					  double torque_applied, std::string *note)
{
	if (frame.id != id_)
		return std::nullopt;
	if (const std::string why = refusal(frame); !why.empty()) {
		if (note)
			*note = "motor " + std::to_string(id_) + ": " + why + ": ignored";
		return std::nullopt;
	}
	switch (mit_special(frame.data)) {
	case MitSpecial::enter:
		enabled_ = true;
		command_ = {};
		break;
	case MitSpecial::exit:
		enabled_ = false;
		command_ = {};
		break;
	case MitSpecial::zero:
		if (std::isfinite(position))
			zero_ = position;
		break;
	case MitSpecial::none:
		command_ = mit_unpack_command(ranges_, frame.data);
		break;
	}
	MitReply reply;
	reply.id = id_;
	reply.position = position - zero_;
	reply.velocity = velocity;
	reply.torque = torque_applied;
	CanFrame out;
	out.extended = reply_id_ > 0x7FF;
	out.id = reply_id_ & (out.extended ? 0x1FFFFFFF : 0x7FF);
	out.len = 6;
	mit_pack_reply(ranges_, reply, out.data);
	return out;
}

double MitMotor::torque(double position, double velocity) const
{
	if (!enabled_ || !std::isfinite(position) || !std::isfinite(velocity))
		return 0;
	const MitCommand &c = command_;
	const double t = c.kp * (c.position - (position - zero_)) + c.kd * (c.velocity - velocity) + c.torque;
	if (std::isnan(t))
		return 0;
	return std::fmin(std::fmax(t, -ranges_.torque_range), ranges_.torque_range);
}

} // namespace tcs
