// The I2C_SMBUS ioctl (wires/i2c/smbus.h): each transaction size as the
// exact I2C messages Linux's emulation sends, what the chip saw, what comes
// back in the union, the bits on the wire, and the kernel's errors for bad
// arguments.
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "i2c_recorder.h"
#include "smbus.h"

namespace {

using tcs::I2cBus;
using tcs::I2cMessage;
using tcs::SmbusResult;

using Bytes = std::vector<uint8_t>;

constexpr uint8_t R = I2C_SMBUS_READ, W = I2C_SMBUS_WRITE;

// The recording chip's bus, and the caller's union.
struct Rig : RecorderRig {
	Rig() { memset(&data, 0, sizeof data); }
	SmbusResult run(uint8_t rw, uint8_t command, uint32_t size, bool ten_bit = false)
	{
		return tcs::i2c_smbus(bus, 0x50, ten_bit, rw, command, size, &data);
	}
	i2c_smbus_data data;
};

void expect_message(const I2cMessage &m, uint16_t flags, const Bytes &data)
{
	assert_int_equal(m.addr, 0x50);
	assert_int_equal(m.flags, flags);
	assert_true(m.data == data);
}

void funcs_are_the_bit_banging_adapters_less_pec(void **)
{
	// I2C 0x1 | 10BIT_ADDR 0x2 | PROTOCOL_MANGLING 0x4 | NOSTART 0x10 | BLOCK_PROC_CALL 0x8000 |
	// QUICK 0x10000 | BYTE 0x60000 | BYTE_DATA 0x180000 | WORD_DATA 0x600000 | PROC_CALL 0x800000 |
	// READ_BLOCK 0x1000000 | WRITE_BLOCK 0x2000000 | I2C_BLOCK 0xC000000; no PEC 0x8.
	assert_int_equal(tcs::i2c_funcs(), 0x0FFF8017);
}

void quick(void **)
{
	Rig rig;
	SmbusResult r = rig.run(W, 0x99, I2C_SMBUS_QUICK);
	assert_int_equal(r.xfer.error, 0);
	assert_int_equal(r.messages.size(), 1);
	expect_message(r.messages[0], 0, {});
	assert_int_equal(r.xfer.bits, 11); // S addr P
	assert_int_equal(r.data_out, 0);
	r = rig.run(R, 0x99, I2C_SMBUS_QUICK);
	expect_message(r.messages[0], I2C_M_RD, {});
	assert_string_equal(rig.chip->log.c_str(), "Sw P Sr P ");
	// Neither uses the union.
	r = tcs::i2c_smbus(rig.bus, 0x50, false, W, 0, I2C_SMBUS_QUICK, nullptr);
	assert_int_equal(r.xfer.error, 0);
}

void byte(void **)
{
	Rig rig;
	rig.chip->replies = { 0x5A };
	SmbusResult r = rig.run(R, 0x33, I2C_SMBUS_BYTE);
	assert_int_equal(r.xfer.error, 0);
	assert_int_equal(r.messages.size(), 1);
	expect_message(r.messages[0], I2C_M_RD, { 0x5A });
	assert_int_equal(rig.data.byte, 0x5A);
	assert_int_equal(r.data_out, 1);
	assert_int_equal(r.xfer.bits, 20);
	// A write sends the command byte alone, without the union.
	r = tcs::i2c_smbus(rig.bus, 0x50, false, W, 0x33, I2C_SMBUS_BYTE, nullptr);
	assert_int_equal(r.xfer.error, 0);
	expect_message(r.messages[0], 0, { 0x33 });
	assert_int_equal(r.data_out, 0);
	assert_string_equal(rig.chip->log.c_str(), "Sr r P Sw w33 P ");
}

void byte_data(void **)
{
	Rig rig;
	rig.chip->replies = { 0xC4 };
	SmbusResult r = rig.run(R, 0x75, I2C_SMBUS_BYTE_DATA);
	assert_int_equal(r.xfer.error, 0);
	assert_int_equal(r.messages.size(), 2);
	expect_message(r.messages[0], 0, { 0x75 });
	expect_message(r.messages[1], I2C_M_RD, { 0xC4 });
	assert_int_equal(rig.data.byte, 0xC4);
	assert_int_equal(r.data_out, 1);
	// S + addr + cmd + Sr + addr + data + P = 1 + 9 + 9 + 1 + 9 + 9 + 1 = 39
	// bits: 390 µs at 100 kHz.
	assert_int_equal(r.xfer.bits, 39);
	assert_int_equal(r.xfer.wire_ns, 390000);

	rig.data.byte = 0x07;
	r = rig.run(W, 0x6B, I2C_SMBUS_BYTE_DATA);
	assert_int_equal(r.messages.size(), 1);
	expect_message(r.messages[0], 0, { 0x6B, 0x07 });
	assert_int_equal(r.xfer.bits, 29);
	assert_int_equal(r.data_out, 0);
	assert_string_equal(rig.chip->log.c_str(), "Sw w75 Sr r P Sw w6b w07 P ");
}

void word_data_is_little_endian(void **)
{
	Rig rig;
	rig.chip->replies = { 0x34, 0x12 };
	SmbusResult r = rig.run(R, 0x10, I2C_SMBUS_WORD_DATA);
	expect_message(r.messages[0], 0, { 0x10 });
	expect_message(r.messages[1], I2C_M_RD, { 0x34, 0x12 });
	assert_int_equal(rig.data.word, 0x1234);
	assert_int_equal(r.data_out, 2);
	assert_int_equal(r.xfer.bits, 1 + 9 + 9 + 1 + 9 + 18 + 1);

	rig.data.word = 0xBEEF;
	r = rig.run(W, 0x11, I2C_SMBUS_WORD_DATA);
	expect_message(r.messages[0], 0, { 0x11, 0xEF, 0xBE });
	assert_int_equal(r.xfer.bits, 1 + 9 + 27 + 1);
}

void proc_call_writes_a_word_and_reads_one(void **)
{
	Rig rig;
	rig.chip->replies = { 0x0A, 0x0B };
	rig.data.word = 0x0102;
	// read_write is WRITE, as i2cset would give it: a read all the same.
	SmbusResult r = rig.run(W, 0x40, I2C_SMBUS_PROC_CALL);
	assert_int_equal(r.xfer.error, 0);
	expect_message(r.messages[0], 0, { 0x40, 0x02, 0x01 });
	expect_message(r.messages[1], I2C_M_RD, { 0x0A, 0x0B });
	assert_int_equal(rig.data.word, 0x0B0A);
	assert_int_equal(r.data_out, 2);
}

void block_data(void **)
{
	Rig rig;
	rig.chip->replies = { 2, 0xAA, 0xBB };
	SmbusResult r = rig.run(R, 0x20, I2C_SMBUS_BLOCK_DATA);
	assert_int_equal(r.xfer.error, 0);
	expect_message(r.messages[0], 0, { 0x20 });
	expect_message(r.messages[1], I2C_M_RD | I2C_M_RECV_LEN, { 2, 0xAA, 0xBB });
	assert_int_equal(rig.data.block[0], 2);
	assert_int_equal(rig.data.block[1], 0xAA);
	assert_int_equal(rig.data.block[2], 0xBB);
	assert_int_equal(r.data_out, 34);
	assert_int_equal(r.xfer.bits, 1 + 9 + 9 + 1 + 9 + 27 + 1);

	// A write sends the count, then the block.
	const uint8_t block[] = { 3, 1, 2, 3 };
	memcpy(rig.data.block, block, sizeof block);
	r = rig.run(W, 0x21, I2C_SMBUS_BLOCK_DATA);
	assert_int_equal(r.xfer.error, 0);
	expect_message(r.messages[0], 0, { 0x21, 3, 1, 2, 3 });
	assert_int_equal(r.xfer.bits, 1 + 9 + 5 * 9 + 1);
	assert_int_equal(r.data_out, 0);
}

void a_bad_block_count_from_the_chip_is_eproto(void **)
{
	for (uint8_t bad : { 0, 33 }) {
		Rig rig;
		rig.chip->replies = { bad, 1, 2 };
		rig.data.block[0] = 0x77;
		const SmbusResult r = rig.run(R, 0x20, I2C_SMBUS_BLOCK_DATA);
		assert_int_equal(r.xfer.error, -EPROTO);
		assert_int_equal(r.data_out, 0);
		assert_int_equal(rig.data.block[0], 0x77); // nothing written back
		assert_int_equal(r.xfer.bits, 1 + 9 + 9 + 1 + 9 + 9 + 1);
	}
}

void block_proc_call(void **)
{
	Rig rig;
	rig.chip->replies = { 1, 0x77 };
	const uint8_t block[] = { 2, 5, 6 };
	memcpy(rig.data.block, block, sizeof block);
	const SmbusResult r = rig.run(W, 0x30, I2C_SMBUS_BLOCK_PROC_CALL);
	assert_int_equal(r.xfer.error, 0);
	expect_message(r.messages[0], 0, { 0x30, 2, 5, 6 });
	expect_message(r.messages[1], I2C_M_RD | I2C_M_RECV_LEN, { 1, 0x77 });
	assert_int_equal(rig.data.block[0], 1);
	assert_int_equal(rig.data.block[1], 0x77);
	assert_int_equal(r.data_out, 34);
}

void i2c_block_data_has_no_count_on_the_wire(void **)
{
	Rig rig;
	rig.chip->replies = { 9, 8, 7 };
	rig.data.block[0] = 3;
	SmbusResult r = rig.run(R, 0x3B, I2C_SMBUS_I2C_BLOCK_DATA);
	assert_int_equal(r.xfer.error, 0);
	expect_message(r.messages[0], 0, { 0x3B });
	expect_message(r.messages[1], I2C_M_RD, { 9, 8, 7 });
	const uint8_t want[] = { 3, 9, 8, 7 };
	assert_memory_equal(rig.data.block, want, sizeof want);
	assert_int_equal(r.data_out, 34);

	const uint8_t block[] = { 2, 0x19, 0x1A };
	memcpy(rig.data.block, block, sizeof block);
	r = rig.run(W, 0x6B, I2C_SMBUS_I2C_BLOCK_DATA);
	expect_message(r.messages[0], 0, { 0x6B, 0x19, 0x1A });

	// A read of none: the command, then a read message of no byte (found
	// by the i2c fuzz target).
	Rig none;
	r = none.run(R, 0x3B, I2C_SMBUS_I2C_BLOCK_DATA);
	assert_int_equal(r.xfer.error, 0);
	expect_message(r.messages[1], I2C_M_RD, {});
	assert_int_equal(r.xfer.bits, 1 + 9 + 9 + 1 + 9 + 1);
	assert_int_equal(r.data_out, 34);
	assert_string_equal(none.chip->log.c_str(), "Sw w3b Sr P ");

	// The old call reads 32, whatever block[0] said.
	Rig old;
	old.data.block[0] = 3;
	r = old.run(R, 0x00, I2C_SMBUS_I2C_BLOCK_BROKEN);
	assert_int_equal(r.xfer.error, 0);
	assert_int_equal(r.messages[1].data.size(), 32);
	assert_int_equal(old.data.block[0], 32);
	assert_int_equal(old.data.block[32], 0xEE);
}

void bad_arguments_are_einval(void **)
{
	Rig rig;
	SmbusResult r = rig.run(R, 0, 9);
	assert_int_equal(r.xfer.error, -EINVAL);
	assert_true(r.messages.empty());
	assert_int_equal(r.xfer.bits, 0);
	assert_false(r.xfer.note.empty());
	assert_int_equal(rig.run(2, 0, I2C_SMBUS_BYTE_DATA).xfer.error, -EINVAL);
	assert_int_equal(rig.run(2, 0, I2C_SMBUS_QUICK).xfer.error, -EINVAL);
	assert_int_equal(tcs::i2c_smbus(rig.bus, 0x50, false, R, 0, I2C_SMBUS_BYTE_DATA, nullptr).xfer.error,
			 -EINVAL);
	assert_int_equal(tcs::i2c_smbus(rig.bus, 0x50, false, R, 0, I2C_SMBUS_BYTE, nullptr).xfer.error, -EINVAL);
	// Blocks over 32 to send; an I2C block read of over 32.
	rig.data.block[0] = 33;
	assert_int_equal(rig.run(W, 0, I2C_SMBUS_BLOCK_DATA).xfer.error, -EINVAL);
	assert_int_equal(rig.run(W, 0, I2C_SMBUS_BLOCK_PROC_CALL).xfer.error, -EINVAL);
	assert_int_equal(rig.run(W, 0, I2C_SMBUS_I2C_BLOCK_DATA).xfer.error, -EINVAL);
	assert_int_equal(rig.run(R, 0, I2C_SMBUS_I2C_BLOCK_DATA).xfer.error, -EINVAL);
	assert_int_equal(rig.run(W, 0, I2C_SMBUS_I2C_BLOCK_BROKEN).xfer.error, -EINVAL);
	// A block read's count comes from the chip: block[0] is not looked at.
	rig.chip->replies = { 1, 5 };
	assert_int_equal(rig.run(R, 0, I2C_SMBUS_BLOCK_DATA).xfer.error, 0);
	assert_string_equal(rig.chip->log.c_str(), "Sw w00 Sr r r P ");
}

void no_chip_is_enxio(void **)
{
	Rig rig;
	rig.data.byte = 0x66;
	const SmbusResult r = tcs::i2c_smbus(rig.bus, 0x51, false, R, 0x75, I2C_SMBUS_BYTE_DATA, &rig.data);
	assert_int_equal(r.xfer.error, -ENXIO);
	assert_int_equal(r.xfer.bits, 11);
	assert_int_equal(r.data_out, 0);
	assert_int_equal(rig.data.byte, 0x66);
}

void ten_bit_flags_every_message(void **)
{
	I2cBus bus;
	assert_true(bus.attach(0x150, std::make_unique<RecordingChip>(), true).ok());
	i2c_smbus_data d;
	memset(&d, 0, sizeof d);
	const SmbusResult r = tcs::i2c_smbus(bus, 0x150, true, R, 1, I2C_SMBUS_WORD_DATA, &d);
	assert_int_equal(r.xfer.error, 0);
	assert_int_equal(r.messages[0].flags, I2C_M_TEN);
	assert_int_equal(r.messages[1].flags, I2C_M_TEN | I2C_M_RD);
	// S + 2 addr + cmd + Sr + 2 addr + Sr + addr(R) + 2 bytes + P
	assert_int_equal(r.xfer.bits, 1 + 18 + 9 + 1 + 18 + 1 + 9 + 18 + 1);
}

void what_the_ioctl_reads_of_the_union(void **)
{
	assert_int_equal(tcs::i2c_smbus_data_in(R, I2C_SMBUS_BYTE_DATA), 0);
	assert_int_equal(tcs::i2c_smbus_data_in(W, I2C_SMBUS_BYTE_DATA), 1);
	assert_int_equal(tcs::i2c_smbus_data_in(W, I2C_SMBUS_WORD_DATA), 2);
	assert_int_equal(tcs::i2c_smbus_data_in(R, I2C_SMBUS_PROC_CALL), 2);
	assert_int_equal(tcs::i2c_smbus_data_in(R, I2C_SMBUS_I2C_BLOCK_DATA), 34);
	assert_int_equal(tcs::i2c_smbus_data_in(R, I2C_SMBUS_BLOCK_PROC_CALL), 34);
	assert_int_equal(tcs::i2c_smbus_data_in(R, I2C_SMBUS_BLOCK_DATA), 0);
	assert_int_equal(tcs::i2c_smbus_data_in(R, I2C_SMBUS_I2C_BLOCK_BROKEN), 0);
	assert_int_equal(tcs::i2c_smbus_data_in(W, I2C_SMBUS_I2C_BLOCK_BROKEN), 34);
	assert_int_equal(tcs::i2c_smbus_data_in(W, I2C_SMBUS_QUICK), 0);
	assert_int_equal(tcs::i2c_smbus_data_in(W, I2C_SMBUS_BYTE), 0);
	assert_int_equal(tcs::i2c_smbus_data_in(W, 9), 0);
	assert_int_equal(tcs::i2c_smbus_data_in(2, I2C_SMBUS_WORD_DATA), 0);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(funcs_are_the_bit_banging_adapters_less_pec),
		cmocka_unit_test(quick),
		cmocka_unit_test(byte),
		cmocka_unit_test(byte_data),
		cmocka_unit_test(word_data_is_little_endian),
		cmocka_unit_test(proc_call_writes_a_word_and_reads_one),
		cmocka_unit_test(block_data),
		cmocka_unit_test(a_bad_block_count_from_the_chip_is_eproto),
		cmocka_unit_test(block_proc_call),
		cmocka_unit_test(i2c_block_data_has_no_count_on_the_wire),
		cmocka_unit_test(bad_arguments_are_einval),
		cmocka_unit_test(no_chip_is_enxio),
		cmocka_unit_test(ten_bit_flags_every_message),
		cmocka_unit_test(what_the_ioctl_reads_of_the_union),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
