// Unit tests for CAN frames from and to SocketCAN's bytes
// (wires/can/can_frame.h): what a CAN_RAW socket's sendmsg refuses, what a
// controller puts on the wire of what it accepts, and the bytes recvmsg gives.
#include <linux/can.h>

#include <cstdint>
#include <cstring>
#include <string>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "can_frame.h"

namespace {

using tcs::CanFrame;

struct can_frame classic(uint32_t can_id, uint8_t len)
{
	struct can_frame f;
	memset(&f, 0, sizeof f);
	f.can_id = can_id;
	f.len = len;
	for (int i = 0; i < 8; i++)
		f.data[i] = uint8_t(0x11 * (i + 1));
	return f;
}

struct canfd_frame fd(uint32_t can_id, uint8_t len, uint8_t flags)
{
	struct canfd_frame f;
	memset(&f, 0, sizeof f);
	f.can_id = can_id;
	f.len = len;
	f.flags = flags;
	for (int i = 0; i < 64; i++)
		f.data[i] = uint8_t(i + 1);
	return f;
}

void classic_frames(void **)
{
	struct can_frame raw = classic(0x123, 3);
	raw.len8_dlc = 12; // ignored: len is not 8, and DLC 8 is sent anyway
	tcs::Result<CanFrame> f = tcs::frame_from_linux(&raw, sizeof raw, false);
	assert_true(f.ok());
	assert_int_equal(f->id, 0x123);
	assert_false(f->extended || f->rtr || f->fd || f->brs || f->esi);
	assert_int_equal(f->len, 3);
	const uint8_t data[8] = { 0x11, 0x22, 0x33, 0, 0, 0, 0, 0 }; // past len: zeros
	assert_memory_equal(f->data, data, 8);
	// An 11-bit id keeps 11 bits; CAN_ERR_FLAG is no frame a controller sends.
	raw = classic(0x7FFFF | CAN_ERR_FLAG, 8);
	f = tcs::frame_from_linux(&raw, sizeof raw, true);
	assert_true(f.ok());
	assert_int_equal(f->id, 0x7FF);
	assert_false(f->extended);
	// Extended and remote: a remote frame carries no data, its len is the DLC.
	raw = classic(0xFFFFFFFF, 5);
	f = tcs::frame_from_linux(&raw, sizeof raw, false);
	assert_true(f.ok());
	assert_int_equal(f->id, 0x1FFFFFFF);
	assert_true(f->extended && f->rtr);
	assert_int_equal(f->len, 5);
	const uint8_t zeros[8] = {};
	assert_memory_equal(f->data, zeros, 8);
}

void refused(void **)
{
	struct canfd_frame raw = fd(0x123, 8, 0);
	// Only CAN_MTU, or CANFD_MTU on an FD socket.
	for (size_t n : { 0, 1, 8, 15, 17, 64, 71, 73 }) {
		tcs::Result<CanFrame> f = tcs::frame_from_linux(&raw, n, true);
		assert_false(f.ok());
		assert_true(f.error().message.find(std::to_string(n) + " bytes") != std::string::npos);
	}
	tcs::Result<CanFrame> f = tcs::frame_from_linux(&raw, CANFD_MTU, false);
	assert_false(f.ok());
	assert_true(f.error().message.find("CAN_RAW_FD_FRAMES") != std::string::npos);
	// len past what the frame holds.
	raw.len = 9;
	assert_false(tcs::frame_from_linux(&raw, CAN_MTU, true).ok());
	raw.len = 65;
	f = tcs::frame_from_linux(&raw, CANFD_MTU, true);
	assert_false(f.ok());
	assert_string_equal(f.error().message.c_str(), "a frame of len 65: at most 64");
	raw.len = 255;
	assert_false(tcs::frame_from_linux(&raw, CANFD_MTU, true).ok());
}

void fd_frames(void **)
{
	struct canfd_frame raw = fd(0x80000456 | CAN_RTR_FLAG, 64, CANFD_BRS | CANFD_ESI);
	tcs::Result<CanFrame> f = tcs::frame_from_linux(&raw, sizeof raw, true);
	assert_true(f.ok());
	assert_true(f->fd && f->extended && f->brs && f->esi);
	assert_false(f->rtr); // FD has no remote frames
	assert_int_equal(f->id, 0x456);
	assert_int_equal(f->len, 64);
	assert_memory_equal(f->data, raw.data, 64);
	// The kernel takes len 9; the controller sends DLC 9, 12 bytes, zeros padding.
	raw = fd(0x1, 9, 0);
	f = tcs::frame_from_linux(&raw, sizeof raw, true);
	assert_true(f.ok());
	assert_int_equal(f->len, 12);
	const uint8_t data[12] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 0, 0 };
	assert_memory_equal(f->data, data, 12);
	assert_int_equal(tcs::can_dlc(*f), 9);
	// The FD lengths and their DLCs.
	assert_int_equal(tcs::can_fd_len(0), 0);
	assert_int_equal(tcs::can_fd_len(8), 8);
	assert_int_equal(tcs::can_fd_len(13), 16);
	assert_int_equal(tcs::can_fd_len(33), 48);
	assert_int_equal(tcs::can_fd_len(49), 64);
	assert_int_equal(tcs::can_fd_len(200), 64);
	CanFrame g;
	g.fd = true;
	g.len = 48;
	assert_int_equal(tcs::can_dlc(g), 14);
	g.len = 20;
	assert_int_equal(tcs::can_dlc(g), 11);
	g.fd = false;
	assert_int_equal(tcs::can_dlc(g), 8);
}

void to_linux(void **)
{
	CanFrame f;
	f.id = 0x1ABCDEF0 & 0x1FFFFFFF;
	f.extended = true;
	f.len = 2;
	f.data[0] = 0xCA;
	f.data[1] = 0xFE;
	assert_int_equal(tcs::linux_frame_size(f), 16);
	uint8_t out[72];
	memset(out, 0xEE, sizeof out);
	tcs::frame_to_linux(f, out, CAN_MTU);
	struct can_frame raw;
	memcpy(&raw, out, sizeof raw);
	assert_int_equal(raw.can_id, 0x9ABCDEF0); // CAN_EFF_FLAG | id
	assert_int_equal(raw.len, 2);
	assert_int_equal(raw.__pad, 0);
	assert_int_equal(raw.len8_dlc, 0);
	const uint8_t data[8] = { 0xCA, 0xFE, 0, 0, 0, 0, 0, 0 };
	assert_memory_equal(raw.data, data, 8);
	assert_int_equal(out[16], 0xEE); // nothing past the mtu
	// A remote frame: the flag, its len, no data.
	f = CanFrame{};
	f.id = 0x7FF;
	f.rtr = true;
	f.len = 4;
	f.data[0] = 1;
	tcs::frame_to_linux(f, out, CAN_MTU);
	memcpy(&raw, out, sizeof raw);
	assert_int_equal(raw.can_id, CAN_RTR_FLAG | 0x7FF);
	assert_int_equal(raw.len, 4);
	assert_int_equal(raw.data[0], 0);
	// FD: CANFD_FDF marks it, as the kernel does since CAN XL.
	f = CanFrame{};
	f.fd = true;
	f.brs = true;
	f.id = 0x10;
	f.len = 12;
	f.data[11] = 0x77;
	assert_int_equal(tcs::linux_frame_size(f), 72);
	tcs::frame_to_linux(f, out, CANFD_MTU);
	struct canfd_frame rawfd;
	memcpy(&rawfd, out, sizeof rawfd);
	assert_int_equal(rawfd.can_id, 0x10);
	assert_int_equal(rawfd.len, 12);
	assert_int_equal(rawfd.flags, CANFD_FDF | CANFD_BRS);
	assert_int_equal(rawfd.data[11], 0x77);
	// And back: the same frame.
	tcs::Result<CanFrame> back = tcs::frame_from_linux(out, CANFD_MTU, true);
	assert_true(back.ok());
	assert_true(back->fd && back->brs && !back->esi && back->len == 12 && back->id == 0x10);
	assert_memory_equal(back->data, f.data, 64);
	// Another mtu writes nothing.
	memset(out, 0xEE, sizeof out);
	tcs::frame_to_linux(f, out, 20);
	assert_int_equal(out[0], 0xEE);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(classic_frames),
		cmocka_unit_test(refused),
		cmocka_unit_test(fd_frames),
		cmocka_unit_test(to_linux),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
