// A CAN frame as it is on the wire, and its conversion from and to the
// bytes of Linux's SocketCAN (struct can_frame, struct canfd_frame of
// <linux/can.h>) as a CAN_RAW socket's sendmsg takes them and its recvmsg
// gives them.
#pragma once

#include <cstddef>
#include <cstdint>

#include "error.h"

namespace tcs {

struct CanFrame {
	uint32_t id = 0;       // 11 bits, or 29 when extended; no flags
	bool extended = false; // 29-bit identifier (CAN_EFF_FLAG)
	bool rtr = false;      // remote frame (classic only)
	bool fd = false;       // CAN FD frame
	bool brs = false;      // FD: the data phase at the data bit rate
	bool esi = false;      // FD: the sender's error-passive flag
	uint8_t len = 0;       // data bytes: 0..8, FD one of 0..8, 12, 16, 20, 24, 32, 48, 64
	uint8_t data[64] = {}; // past len: zeros
};

// The FD length that holds len bytes: the next of 0..8, 12, 16, 20, 24, 32,
// 48, 64 (64 for anything longer).
uint8_t can_fd_len(size_t len);
// The 4-bit DLC that a frame of len bytes sends (len as can_fd_len rounds
// it; classic: at most 8).
uint8_t can_dlc(const CanFrame &frame);

// The frame a CAN_RAW socket's sendmsg takes from n bytes, refused as the
// kernel refuses it (every refusal is its EINVAL; the text says why): n
// must be CAN_MTU (16), or CANFD_MTU (72) when fd_enabled (the socket has
// CAN_RAW_FD_FRAMES and the interface CANFD_MTU); len at most 8, or 64.
// What the kernel passes on and a controller puts on the wire differently
// is taken as the controller sends it:
//  - an FD len the kernel accepts but no DLC encodes (9..11, 13..15, ...)
//    is padded with zeros up to the next FD length, as the drivers do;
//  - the identifier is masked to 11 or 29 bits; CAN_ERR_FLAG is dropped
//    (no controller sends an error frame on request);
//  - an FD frame's CAN_RTR_FLAG is dropped (FD has no remote frames);
//    a remote frame's data bytes and the bytes past len are zeros;
//  - len8_dlc is ignored (DLC 8 is sent: an interface without the
//    cc-len8-dlc mode, the default); ESI is kept as given (as vcan does).
Result<CanFrame> frame_from_linux(const void *bytes, size_t n, bool fd_enabled);

// What recvmsg gives for the frame: CAN_MTU bytes for a classic frame,
// CANFD_MTU for an FD one.
size_t linux_frame_size(const CanFrame &frame);
// Writes the frame as a struct can_frame (mtu CAN_MTU: an FD frame's first
// 8 bytes) or a struct canfd_frame (mtu CANFD_MTU: CANFD_FDF set for an FD
// frame, as the kernel since CAN XL does); another mtu writes nothing.
void frame_to_linux(const CanFrame &frame, void *out, size_t mtu);

} // namespace tcs
