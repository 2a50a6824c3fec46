// I2cBus (wires/i2c/i2c_bus.h): combined transfers, NACKs and the flags of
// <linux/i2c.h>, with the bits each costs counted by hand: START 1, an
// address byte 9, a data byte 9 (8 without its ACK bit), a repeated START
// 1, STOP 1.
#include <cerrno>
#include <cstdint>
#include <memory>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "i2c_bus.h"
#include "i2c_recorder.h"

namespace {

using tcs::I2cBus;
using tcs::I2cMessage;
using tcs::I2cResult;

using Bytes = std::vector<uint8_t>;

using Rig = RecorderRig;

I2cMessage msg(uint16_t addr, uint16_t flags, Bytes data)
{
	return I2cMessage{ addr, flags, std::move(data) };
}

void bit_times_at_any_clock(void **)
{
	assert_int_equal(tcs::i2c_bits_ns(39, 100000), 390000);
	assert_int_equal(tcs::i2c_bits_ns(39, 400000), 97500);
	assert_int_equal(tcs::i2c_bits_ns(38, 300000), 126667); // 126666.67 ns
	assert_int_equal(tcs::i2c_bits_ns(1, 3), 333333333);
	assert_int_equal(tcs::i2c_bits_ns(0, 100000), 0);
	assert_int_equal(tcs::i2c_bits_ns(5, 0), 0);
	assert_int_equal(I2cBus(0).clock_hz(), 100000);
	assert_int_equal(I2cBus(-5).clock_hz(), 100000);
	assert_int_equal(I2cBus(400000).clock_hz(), 400000);
}

void a_write_then_a_read(void **)
{
	Rig rig;
	rig.chip->replies = { 0xAB, 0xCD };
	std::vector<I2cMessage> m = { msg(0x50, 0, { 0x10 }), msg(0x50, I2C_M_RD, Bytes(2)) };
	const I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.done, 2);
	// S + addr + 0x10 + Sr + addr + 2 bytes + P = 1 + 9 + 9 + 1 + 9 + 18 + 1
	assert_int_equal(r.bits, 48);
	assert_int_equal(r.wire_ns, 480000);
	assert_true(m[1].data == (Bytes{ 0xAB, 0xCD }));
	assert_string_equal(rig.chip->log.c_str(), "Sw w10 Sr r r P ");
	assert_true(r.note.empty());
}

void an_empty_address_is_nacked(void **)
{
	Rig rig;
	std::vector<I2cMessage> m = { msg(0x51, 0, { 1, 2 }) };
	I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, -ENXIO);
	assert_int_equal(r.done, 0);
	assert_int_equal(r.bits, 11); // S + addr + P
	assert_int_equal(r.wire_ns, 110000);
	assert_false(r.note.empty());
	assert_string_equal(rig.chip->log.c_str(), "");

	// The transfer stops at the NACK: the chip's message went, then STOP.
	m = { msg(0x50, 0, { 1 }), msg(0x51, I2C_M_RD, Bytes(4)), msg(0x50, 0, { 2 }) };
	r = rig.bus.transfer(m);
	assert_int_equal(r.error, -ENXIO);
	assert_int_equal(r.done, 1);
	assert_int_equal(r.bits, 1 + 9 + 9 + 1 + 9 + 1);
	assert_string_equal(rig.chip->log.c_str(), "Sw w01 P ");
}

void ignore_nak_goes_on(void **)
{
	Rig rig;
	rig.chip->replies = { 0x42 };
	std::vector<I2cMessage> m = { msg(0x51, I2C_M_IGNORE_NAK, { 1, 2 }),
				      msg(0x51, I2C_M_RD | I2C_M_IGNORE_NAK, Bytes(1)), msg(0x50, I2C_M_RD, Bytes(1)) };
	const I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.done, 3);
	assert_int_equal(r.bits, 1 + 27 + 1 + 18 + 1 + 18 + 1);
	assert_int_equal(m[1].data[0], 0xFF); // nothing drives SDA: the pull-ups
	assert_int_equal(m[2].data[0], 0x42);
	assert_string_equal(rig.chip->log.c_str(), "Sr r P ");
}

void a_nacked_byte_fails_with_eio(void **)
{
	Rig rig;
	rig.chip->ack_writes = 1;
	std::vector<I2cMessage> m = { msg(0x50, 0, { 1, 2, 3 }) };
	I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, -EIO);
	assert_int_equal(r.done, 0);
	assert_int_equal(r.bits, 1 + 9 + 9 + 9 + 1); // up to the NACKed byte
	assert_string_equal(rig.chip->log.c_str(), "Sw w01 w02 P ");

	rig.chip->log.clear();
	m = { msg(0x50, I2C_M_IGNORE_NAK, { 4, 5 }) };
	r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.bits, 1 + 9 + 18 + 1);
	assert_string_equal(rig.chip->log.c_str(), "Sw w04 w05 P ");
}

void recv_len_reads_the_count_then_the_block(void **)
{
	Rig rig;
	rig.chip->replies = { 3, 0xA1, 0xA2, 0xA3, 0x99 };
	std::vector<I2cMessage> m = { msg(0x50, 0, { 0x20 }), msg(0x50, I2C_M_RD | I2C_M_RECV_LEN, Bytes(1)) };
	I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_true(m[1].data == (Bytes{ 3, 0xA1, 0xA2, 0xA3 }));
	assert_int_equal(r.bits, 1 + 9 + 9 + 1 + 9 + 4 * 9 + 1);

	// A count of 0 or over 32: -EPROTO after the count byte.
	for (uint8_t bad : { 0, 33, 255 }) {
		rig.chip->replies = { bad };
		m = { msg(0x50, 0, { 0x20 }), msg(0x50, I2C_M_RD | I2C_M_RECV_LEN, Bytes(1)) };
		r = rig.bus.transfer(m);
		assert_int_equal(r.error, -EPROTO);
		assert_int_equal(r.done, 1);
		assert_int_equal(r.bits, 1 + 9 + 9 + 1 + 9 + 9 + 1);
	}
	// 32 is the most.
	rig.chip->replies = { 32 };
	m = { msg(0x50, I2C_M_RD | I2C_M_RECV_LEN, Bytes(1)) };
	r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(m[0].data.size(), 33);
	assert_int_equal(m[0].data[32], 0xEE);
}

void ten_bit_addresses(void **)
{
	I2cBus bus(100000);
	auto c = std::make_unique<RecordingChip>();
	RecordingChip *chip = c.get();
	assert_true(bus.attach(0x2A5, std::move(c), true).ok());
	assert_null(bus.chip(0x2A5));
	assert_ptr_equal(bus.chip(0x2A5, true), chip);
	chip->replies = { 0x77 };

	std::vector<I2cMessage> m = { msg(0x2A5, I2C_M_TEN, { 1 }) };
	I2cResult r = bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.bits, 1 + 18 + 9 + 1); // two address bytes
	// A read: S 11110xx0 A7..A0 Sr 11110xx1, then the byte.
	m = { msg(0x2A5, I2C_M_TEN | I2C_M_RD, Bytes(1)) };
	r = bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(m[0].data[0], 0x77);
	assert_int_equal(r.bits, 1 + 18 + 1 + 9 + 9 + 1);
	assert_string_equal(chip->log.c_str(), "Sw w01 P Sw Sr r P ");

	// Same A9 A8: the first byte is ACKed, the second NACKed.
	m = { msg(0x2A6, I2C_M_TEN, { 1 }) };
	r = bus.transfer(m);
	assert_int_equal(r.error, -ENXIO);
	assert_int_equal(r.bits, 1 + 18 + 1);
	// Other A9 A8: NACKed at the first; and a 7-bit 0x25 is another chip.
	m = { msg(0x1A5, I2C_M_TEN, { 1 }) };
	assert_int_equal(bus.transfer(m).bits, 1 + 9 + 1);
	m = { msg(0x25, 0, { 1 }) };
	assert_int_equal(bus.transfer(m).error, -ENXIO);
}

void reads_without_their_ack_bit(void **)
{
	Rig rig;
	std::vector<I2cMessage> m = { msg(0x50, I2C_M_RD | I2C_M_NO_RD_ACK, Bytes(2)) };
	const I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.bits, 1 + 9 + 8 + 8 + 1);
}

void stop_and_nostart_between_messages(void **)
{
	Rig rig;
	// I2C_M_STOP: P and S in place of Sr, and the chip sees the STOP.
	std::vector<I2cMessage> m = { msg(0x50, I2C_M_STOP, { 1 }), msg(0x50, 0, { 2 }) };
	I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.bits, 1 + 9 + 9 + 1 + 1 + 9 + 9 + 1);
	assert_string_equal(rig.chip->log.c_str(), "Sw w01 P Sw w02 P ");

	// I2C_M_NOSTART: the bytes follow on, no START nor address.
	rig.chip->log.clear();
	m = { msg(0x50, 0, { 1 }), msg(0x51, I2C_M_NOSTART, { 2, 3 }) };
	r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.done, 2);
	assert_int_equal(r.bits, 1 + 9 + 9 + 18 + 1);
	assert_string_equal(rig.chip->log.c_str(), "Sw w01 w02 w03 P ");

	// On the first message no chip is addressed: its byte is NACKed.
	rig.chip->log.clear();
	m = { msg(0x50, I2C_M_NOSTART, { 1 }) };
	r = rig.bus.transfer(m);
	assert_int_equal(r.error, -EIO);
	assert_int_equal(r.bits, 1 + 9 + 1);
	assert_string_equal(rig.chip->log.c_str(), "");
}

void rev_dir_addr_inverts_the_rw_bit(void **)
{
	Rig rig;
	std::vector<I2cMessage> m = { msg(0x50, I2C_M_REV_DIR_ADDR, { 9 }) };
	const I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_string_equal(rig.chip->log.c_str(), "Sr w09 P ");
}

void an_address_is_its_low_bits(void **)
{
	// struct i2c_msg's addr is 16 bits; a 7-bit address sends its low 7.
	Rig rig;
	std::vector<I2cMessage> m = { msg(0x50 | 0x80, 0, { 1 }) };
	assert_int_equal(rig.bus.transfer(m).error, 0);
	assert_string_equal(rig.chip->log.c_str(), "Sw w01 P ");
}

void no_messages_is_a_start_and_a_stop(void **)
{
	Rig rig;
	std::vector<I2cMessage> m;
	const I2cResult r = rig.bus.transfer(m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.done, 0);
	assert_int_equal(r.bits, 2);
}

void attach_checks_its_address(void **)
{
	I2cBus bus;
	assert_true(bus.attach(0x7F, std::make_unique<RecordingChip>()).ok());
	assert_false(bus.attach(0x80, std::make_unique<RecordingChip>()).ok());
	assert_false(bus.attach(0x7F, std::make_unique<RecordingChip>()).ok()); // taken
	assert_true(bus.attach(0x7F, std::make_unique<RecordingChip>(), true).ok());
	assert_true(bus.attach(0x3FF, std::make_unique<RecordingChip>(), true).ok());
	assert_false(bus.attach(0x400, std::make_unique<RecordingChip>(), true).ok());
	assert_false(bus.attach(0x10, nullptr).ok());
	assert_non_null(bus.chip(0x7F));
	assert_null(bus.chip(0x10));
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(bit_times_at_any_clock),
		cmocka_unit_test(a_write_then_a_read),
		cmocka_unit_test(an_empty_address_is_nacked),
		cmocka_unit_test(ignore_nak_goes_on),
		cmocka_unit_test(a_nacked_byte_fails_with_eio),
		cmocka_unit_test(recv_len_reads_the_count_then_the_block),
		cmocka_unit_test(ten_bit_addresses),
		cmocka_unit_test(reads_without_their_ack_bit),
		cmocka_unit_test(stop_and_nostart_between_messages),
		cmocka_unit_test(rev_dir_addr_inverts_the_rw_bit),
		cmocka_unit_test(an_address_is_its_low_bits),
		cmocka_unit_test(no_messages_is_a_start_and_a_stop),
		cmocka_unit_test(attach_checks_its_address),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
