// The MIT mini-cheetah actuator protocol's frames, as T-Motor AK and
// CubeMars drives speak it: a value is a w-bit unsigned integer mapped
// linearly on [min, max] (raw = (x − min)·(2^w − 1)/(max − min), truncated,
// as the firmware's float_to_uint does; x is first clamped to [min, max],
// NaN to min). Position 16 bits on ±position_range; velocity 12 bits on
// ±velocity_range; kp, kd 12 bits on [0, kp_max], [0, kd_max]; torque 12
// bits on ±torque_range.
//
// Command (8 bytes, on the motor's id): p[15:8] p[7:0] v[11:4]
// v[3:0]<<4|kp[11:8] kp[7:0] kd[11:4] kd[3:0]<<4|t[11:8] t[7:0].
// Reply (6 bytes): id p[15:8] p[7:0] v[11:4] v[3:0]<<4|t[11:8] t[7:0].
// Special commands: FF FF FF FF FF FF FF then FC (enter motor mode), FD
// (exit it), FE (the current position is zero).
#pragma once

#include <cstdint>

#include "can_frame.h"

namespace tcs {

struct MitRanges {
	double position_range = 12.5; // rad, ±
	double velocity_range = 50;   // rad/s, ±
	double torque_range = 5;      // N·m, ±
	double kp_max = 500;          // N·m/rad, [0, kp_max]
	double kd_max = 5;            // N·m·s/rad, [0, kd_max]
};

struct MitCommand {
	double position = 0, velocity = 0, kp = 0, kd = 0, torque = 0;
};

struct MitReply {
	uint8_t id = 0;
	double position = 0, velocity = 0, torque = 0;
};

enum class MitSpecial { none, enter, exit, zero };

// x on [min, max] as a bits-wide unsigned integer, and back.
uint32_t mit_to_uint(double x, double min, double max, int bits);
double mit_from_uint(uint32_t raw, double min, double max, int bits);

// The 8 bytes of a command, and the command they carry.
void mit_pack_command(const MitRanges &ranges, const MitCommand &command, uint8_t out[8]);
MitCommand mit_unpack_command(const MitRanges &ranges, const uint8_t in[8]);
// Which special command 8 bytes are, if any.
MitSpecial mit_special(const uint8_t in[8]);
// The 6 bytes of a reply, and the reply they carry.
void mit_pack_reply(const MitRanges &ranges, const MitReply &reply, uint8_t out[6]);
MitReply mit_unpack_reply(const MitRanges &ranges, const uint8_t in[6]);

} // namespace tcs
