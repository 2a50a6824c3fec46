// The MIT mini-cheetah protocol's fields packed and unpacked (see mit_codec.h).
#include "mit_codec.h"

#include <cmath>

namespace tcs {

namespace {

uint32_t top(int bits)
{
	return (uint32_t(1) << bits) - 1;
}

} // namespace

uint32_t mit_to_uint(double x, double min, double max, int bits)
{
	const double span = max - min;
	if (!(span > 0) || !std::isfinite(span) || std::isnan(x))
		return 0;
	x = std::fmin(std::fmax(x, min), max);
	const double v = (x - min) * top(bits) / span;
	if (!(v > 0))
		return 0;
	return v >= top(bits) ? top(bits) : uint32_t(v);
}

double mit_from_uint(uint32_t raw, double min, double max, int bits)
{
	return double(raw & top(bits)) * (max - min) / top(bits) + min;
}

void mit_pack_command(const MitRanges &r, const MitCommand &c, uint8_t out[8])
{
	const uint32_t p = mit_to_uint(c.position, -r.position_range, r.position_range, 16);
	const uint32_t v = mit_to_uint(c.velocity, -r.velocity_range, r.velocity_range, 12);
	const uint32_t kp = mit_to_uint(c.kp, 0, r.kp_max, 12);
	const uint32_t kd = mit_to_uint(c.kd, 0, r.kd_max, 12);
	const uint32_t t = mit_to_uint(c.torque, -r.torque_range, r.torque_range, 12);
	out[0] = uint8_t(p >> 8);
	out[1] = uint8_t(p);
	out[2] = uint8_t(v >> 4);
	out[3] = uint8_t((v & 0xF) << 4 | kp >> 8);
	out[4] = uint8_t(kp);
	out[5] = uint8_t(kd >> 4);
	out[6] = uint8_t((kd & 0xF) << 4 | t >> 8);
	out[7] = uint8_t(t);
}

MitCommand mit_unpack_command(const MitRanges &r, const uint8_t in[8])
{
	const uint32_t p = uint32_t(in[0]) << 8 | in[1];
	const uint32_t v = uint32_t(in[2]) << 4 | in[3] >> 4;
	const uint32_t kp = uint32_t(in[3] & 0xF) << 8 | in[4];
	const uint32_t kd = uint32_t(in[5]) << 4 | in[6] >> 4;
	const uint32_t t = uint32_t(in[6] & 0xF) << 8 | in[7];
	MitCommand c;
	c.position = mit_from_uint(p, -r.position_range, r.position_range, 16);
	c.velocity = mit_from_uint(v, -r.velocity_range, r.velocity_range, 12);
	c.kp = mit_from_uint(kp, 0, r.kp_max, 12);
	c.kd = mit_from_uint(kd, 0, r.kd_max, 12);
	c.torque = mit_from_uint(t, -r.torque_range, r.torque_range, 12);
	return c;
}

MitSpecial mit_special(const uint8_t in[8])
{
	for (int i = 0; i < 7; i++)
		if (in[i] != 0xFF)
			return MitSpecial::none;
	switch (in[7]) {
	case 0xFC:
		return MitSpecial::enter;
	case 0xFD:
		return MitSpecial::exit;
	case 0xFE:
		return MitSpecial::zero;
	default:
		return MitSpecial::none;
	}
}

void mit_pack_reply(const MitRanges &r, const MitReply &reply, uint8_t out[6])
{
	const uint32_t p = mit_to_uint(reply.position, -r.position_range, r.position_range, 16);
	const uint32_t v = mit_to_uint(reply.velocity, -r.velocity_range, r.velocity_range, 12);
	const uint32_t t = mit_to_uint(reply.torque, -r.torque_range, r.torque_range, 12);
	out[0] = reply.id;
	out[1] = uint8_t(p >> 8);
	out[2] = uint8_t(p);
	out[3] = uint8_t(v >> 4);
	out[4] = uint8_t((v & 0xF) << 4 | t >> 8);
	out[5] = uint8_t(t);
}

MitReply mit_unpack_reply(const MitRanges &r, const uint8_t in[6])
{
	MitReply reply;
	reply.id = in[0];
	reply.position = mit_from_uint(uint32_t(in[1]) << 8 | in[2], -r.position_range, r.position_range, 16);
	reply.velocity = mit_from_uint(uint32_t(in[3]) << 4 | in[4] >> 4, -r.velocity_range, r.velocity_range, 12);
	reply.torque = mit_from_uint(uint32_t(in[4] & 0xF) << 8 | in[5], -r.torque_range, r.torque_range, 12);
	return reply;
}

} // namespace tcs
