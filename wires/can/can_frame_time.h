// How long a frame occupies the bus: its bits as ISO 11898-1 sends them,
// stuff bits included, counted from the frame's actual content.
//
// Classic frames: SOF, arbitration (11-bit id, RTR, IDE; or 11-bit base,
// SRR, IDE, 18-bit extension, RTR), control (r0, or r1 r0; 4-bit DLC),
// the data, CRC-15 (polynomial 0x4599 over SOF..data), then the CRC
// delimiter, ACK slot and delimiter, 7 bits of EOF and 3 of intermission:
// 47 + 8·len bits for a standard data frame, 67 + 8·len for an extended
// one, a remote frame without data bits (its DLC still sent). A stuff bit
// follows every five equal bits from SOF to the end of the CRC sequence
// (the stuff bits themselves counting towards the next five), one after
// the CRC's last bits included.
//
// CAN FD frames (ISO CRC): SOF, the id (RRS, IDE; or SRR, IDE, extension,
// RRS), FDF, res, BRS, ESI, DLC, data, then the CRC field: the 4-bit
// stuff count and CRC-17 (len ≤ 16) or CRC-21, with fixed stuff bits, one
// before the stuff count and one after every fourth bit: 6 for CRC-17, 7
// for CRC-21. Dynamic stuff bits are counted from the content from SOF to
// the end of the data; where five equal bits end the data, the first fixed
// stuff bit is the stuff bit (none is added). The CRC field's length does
// not depend on its value, so the count is exact without CRC-17/21. With
// BRS, the bits after BRS up to the end of the CRC sequence (the stuff
// bits among them) take the data bit rate, the rest the nominal one: the
// switch happens at the sample points of BRS and the CRC delimiter, which
// this counts as whole nominal bits.
#pragma once

#include <cstdint>

#include "can_frame.h"

namespace tcs {

struct CanFrameBits {
	int nominal = 0; // at the nominal bit rate, the 3 bits of intermission included
	int data = 0;    // at the data bit rate (FD frames with BRS), else 0
};

// A frame's len past what its kind holds counts as the largest (8), an FD
// len that no DLC encodes as the next FD length (can_fd_len).
CanFrameBits can_frame_bit_split(const CanFrame &frame);
// All of them: nominal + data.
int can_frame_bits(const CanFrame &frame);

// One bit's time in integer nanoseconds: 1e9 / bitrate rounded to the
// nearest (1000 at 1 Mbit/s, 30000 at 33.333 kbit/s), at least 1; a
// bitrate under 1 counts as 1 bit/s. Whole nanoseconds a bit make frames
// sent back to back end at exactly the sum of their times.
int64_t can_bit_ns(int64_t bitrate);
// The frame's time on the wire: its nominal bits at bitrate, its data
// phase at data_bitrate (≤ 0: bitrate).
int64_t can_frame_ns(const CanFrame &frame, int64_t bitrate, int64_t data_bitrate);

} // namespace tcs
