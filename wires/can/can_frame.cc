// CanFrame from and to SocketCAN's bytes (see can_frame.h).
#include "can_frame.h"

#include <linux/can.h>

#include <algorithm>
#include <cstring>
#include <string>

namespace tcs {

namespace {

static_assert(CAN_MTU == 16 && CANFD_MTU == 72);

// The FD lengths, by DLC.
constexpr uint8_t kFdLen[16] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64 };

} // namespace

uint8_t can_fd_len(size_t len)
{
	for (uint8_t l : kFdLen)
		if (len <= l)
			return l;
	return 64;
}

uint8_t can_dlc(const CanFrame &frame)
{
	if (!frame.fd)
		return std::min<uint8_t>(frame.len, 8);
	const uint8_t len = can_fd_len(frame.len);
	uint8_t dlc = 0;
	while (kFdLen[dlc] != len)
		dlc++;
	return dlc;
}

Result<CanFrame> frame_from_linux(const void *bytes, size_t n, bool fd_enabled)
{
	if (n != CAN_MTU && !(fd_enabled && n == CANFD_MTU))
		return Error{ "a frame of " + std::to_string(n) + " bytes: a CAN_RAW socket takes " +
			      std::to_string(CAN_MTU) + (fd_enabled ? " or " + std::to_string(CANFD_MTU) : "") +
			      (fd_enabled ? "" : " (CAN FD frames need CAN_RAW_FD_FRAMES and an FD interface)") };
	// struct canfd_frame's first 8 bytes are laid out as can_frame's.
	struct canfd_frame raw;
	memset(&raw, 0, sizeof raw);
	memcpy(&raw, bytes, n);
	CanFrame f;
	f.fd = n == CANFD_MTU;
	const size_t max = f.fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN;
	if (raw.len > max)
		return Error{ "a frame of len " + std::to_string(raw.len) + ": at most " + std::to_string(max) };
	f.extended = raw.can_id & CAN_EFF_FLAG;
	f.id = raw.can_id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
	f.rtr = !f.fd && (raw.can_id & CAN_RTR_FLAG);
	if (f.fd) {
		f.brs = raw.flags & CANFD_BRS;
		f.esi = raw.flags & CANFD_ESI;
	}
	f.len = f.fd ? can_fd_len(raw.len) : raw.len;
	if (!f.rtr)
		memcpy(f.data, raw.data, raw.len);
	return f;
}

size_t linux_frame_size(const CanFrame &frame)
{
	return frame.fd ? CANFD_MTU : CAN_MTU;
}

void frame_to_linux(const CanFrame &frame, void *out, size_t mtu)
{
	if (mtu != CAN_MTU && mtu != CANFD_MTU)
		return;
	struct canfd_frame raw;
	memset(&raw, 0, sizeof raw);
	raw.can_id = frame.id & (frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
	if (frame.extended)
		raw.can_id |= CAN_EFF_FLAG;
	if (frame.rtr && !frame.fd)
		raw.can_id |= CAN_RTR_FLAG;
	const size_t room = mtu == CAN_MTU ? CAN_MAX_DLEN : CANFD_MAX_DLEN;
	raw.len = (uint8_t)std::min<size_t>(frame.fd ? can_fd_len(frame.len) : std::min<uint8_t>(frame.len, 8), room);
	if (mtu == CANFD_MTU && frame.fd)
		raw.flags = CANFD_FDF | (frame.brs ? CANFD_BRS : 0) | (frame.esi ? CANFD_ESI : 0);
	if (!(frame.rtr && !frame.fd))
		memcpy(raw.data, frame.data, raw.len);
	memcpy(out, &raw, mtu);
}

} // namespace tcs
