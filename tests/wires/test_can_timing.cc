// Unit tests for a CAN frame's bits on the wire (wires/can/can_frame_time.h).
// The expected counts were worked out from ISO 11898-1 by hand: the frame's
// bits written out, its CRC-15 as the remainder of the polynomial division
// of Bosch's CAN 2.0 spec, and the stuff bits counted on the bit string.
#include <cstdint>
#include <cstring>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "can_frame_time.h"
#include "can_test_frames.h"

namespace {

using tcs::CanFrame;

CanFrame fd_frame(uint32_t id, uint8_t len, uint8_t fill, bool brs)
{
	CanFrame f;
	f.id = id;
	f.fd = true;
	f.brs = brs;
	f.len = len;
	memset(f.data, fill, len);
	return f;
}

void zeros_stuff_most(void **)
{
	// 0 + 11·0 + RTR IDE r0 = 15 zeros (3 stuff bits), DLC 1000, 64 zeros
	// (13 more: the run of DLC's three zeros goes on into the data), then
	// CRC 0x145B = 101000101011011: no run of five.
	assert_int_equal(tcs::can_frame_bits(can_test_frame(0x000, { 0, 0, 0, 0, 0, 0, 0, 0 })), 47 + 64 + 16);
	// No data: 34 zeros (CRC 0), a stuff bit after each five.
	assert_int_equal(tcs::can_frame_bits(can_test_frame(0x000, {})), 47 + 6);
}

void ones_stuff(void **)
{
	// 0, 11 ones (2 stuff bits), 000 1000, 64 ones (12), then CRC 0x4C89
	// = 100110010001001 after four ones: the 5th one takes a stuff bit.
	assert_int_equal(tcs::can_frame_bits(can_test_frame(0x7FF, { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF })),
			 47 + 64 + 15);
	// The MIT motor's "enter motor mode" to motor 1: 0 + 10 zeros (2 stuff
	// bits), 1, 000 1000, 62 ones (12), 00, CRC 0x72B8.
	assert_int_equal(tcs::can_frame_bits(can_test_frame(0x001, { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFC })),
			 47 + 64 + 14);
}

void no_stuffing(void **)
{
	// 0 10101010101 000 0100, 10101010 ×4, CRC 0x1C47 = 001110001000111:
	// no five equal bits anywhere.
	assert_int_equal(tcs::can_frame_bits(can_test_frame(0x555, { 0xAA, 0xAA, 0xAA, 0xAA })), 47 + 32);
	// 0x55 ×6, DLC 0110, CRC 0x3B0D = 011101100001101: the same.
	assert_int_equal(tcs::can_frame_bits(can_test_frame(0x555, { 0x55, 0x55, 0x55, 0x55, 0x55, 0x55 })), 47 + 48);
	// Eight of them: the CRC 0x1B04 = 001101100000100 has five zeros.
	assert_int_equal(tcs::can_frame_bits(can_test_frame(0x555, { 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55 })),
			 47 + 64 + 1);
}

void extended_and_remote(void **)
{
	// 0, base 0x048, SRR IDE 11, extension 0x05678, RTR r1 r0, DLC 1000,
	// 01..08, CRC 0x221A: 9 stuff bits.
	CanFrame f = can_test_frame(0x12345678, { 1, 2, 3, 4, 5, 6, 7, 8 }, true);
	assert_int_equal(tcs::can_frame_bits(f), 67 + 64 + 9);
	// All 29 bits recessive, a remote frame of DLC 0: 0, 32 ones (6 stuff
	// bits), r1 r0 0000 (one more), CRC 0x6F4D = 110111101001101.
	f = can_test_frame(0x1FFFFFFF, {}, true);
	f.rtr = true;
	assert_int_equal(tcs::can_frame_bits(f), 67 + 7);
	// A remote frame sends its DLC (8) but no data: 0 00100100011 100 1000,
	// CRC 0x6F9A = 110111110011010: five ones.
	f = can_test_frame(0x123, { 1, 2, 3, 4, 5, 6, 7, 8 });
	f.rtr = true;
	assert_int_equal(tcs::can_frame_bits(f), 47 + 1);
	// A classic len over 8 sends DLC 8 and 8 bytes.
	f = can_test_frame(0x555, { 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55 });
	f.len = 15;
	assert_int_equal(tcs::can_frame_bits(f), 47 + 64 + 1);
}

void fd_frames(void **)
{
	// 0 00100100011 RRS IDE FDF res BRS (0 0 1 0 1): 17 nominal bits; ESI
	// and DLC 0000 are five zeros ending the dynamic stuffing, where the
	// fixed stuff bit stands in. Then stuff count, CRC-17, 6 fixed stuff bits.
	tcs::CanFrameBits b = tcs::can_frame_bit_split(fd_frame(0x123, 0, 0, true));
	assert_int_equal(b.nominal, 17 + 13);
	assert_int_equal(b.data, 5 + 4 + 17 + 6);
	// Without BRS everything is nominal, and res BRS ESI DLC are seven
	// zeros: a stuff bit after the fifth.
	b = tcs::can_frame_bit_split(fd_frame(0x123, 0, 0, false));
	assert_int_equal(b.nominal, 62 + 1);
	assert_int_equal(b.data, 0);
	// 14 zeros (2 stuff bits before BRS), FDF res BRS ESI = 1010, DLC 1000,
	// 64 zeros: 13 stuff bits after BRS.
	b = tcs::can_frame_bit_split(fd_frame(0x000, 8, 0, true));
	assert_int_equal(b.nominal, 17 + 2 + 13);
	assert_int_equal(b.data, 5 + 64 + 13 + 4 + 17 + 6);
	// 0x55 data: no stuffing; 12 bytes CRC-17, 20 bytes CRC-21 (7 fixed
	// stuff bits).
	assert_int_equal(tcs::can_frame_bits(fd_frame(0x555, 12, 0x55, false)), 22 + 96 + 27 + 13);
	assert_int_equal(tcs::can_frame_bits(fd_frame(0x555, 20, 0x55, false)), 22 + 160 + 32 + 13);
	// A len no DLC encodes counts as the next FD length (9 → 12), padded
	// with zeros: 24 of them after the last 1, 4 stuff bits.
	assert_int_equal(tcs::can_frame_bits(fd_frame(0x555, 9, 0x55, false)), 22 + 96 + 4 + 27 + 13);
}

void frame_times(void **)
{
	assert_int_equal(tcs::can_bit_ns(1000000), 1000);
	assert_int_equal(tcs::can_bit_ns(500000), 2000);
	assert_int_equal(tcs::can_bit_ns(33333), 30000);      // 30000.3
	assert_int_equal(tcs::can_bit_ns(3000000), 333);      // 333.3
	assert_int_equal(tcs::can_bit_ns(1500000), 667);      // 666.7
	assert_int_equal(tcs::can_bit_ns(2000000000), 1);     // at least 1
	assert_int_equal(tcs::can_bit_ns(0), 1000000000);     // as 1 bit/s
	CanFrame f = can_test_frame(0x000, { 0, 0, 0, 0, 0, 0, 0, 0 }); // 127 bits
	assert_int_equal(tcs::can_frame_ns(f, 1000000, 0), 127000);
	assert_int_equal(tcs::can_frame_ns(f, 125000, 2000000), 127 * 8000);
	// FD with BRS at 1 and 5 Mbit/s: 32 nominal bits, 109 data bits.
	assert_int_equal(tcs::can_frame_ns(fd_frame(0x000, 8, 0, true), 1000000, 5000000), 32 * 1000 + 109 * 200);
	// No data bit rate: the data phase at the nominal one.
	assert_int_equal(tcs::can_frame_ns(fd_frame(0x000, 8, 0, true), 1000000, 0), 141 * 1000);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(zeros_stuff_most),    cmocka_unit_test(ones_stuff), cmocka_unit_test(no_stuffing),
		cmocka_unit_test(extended_and_remote), cmocka_unit_test(fd_frames),  cmocka_unit_test(frame_times),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
