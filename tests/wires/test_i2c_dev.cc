// i2c-dev's rules (wires/i2c/i2c_dev.h): I2C_SLAVE's address check, the
// arguments I2C_RDWR refuses with -EINVAL before the bus, its
// I2C_M_RECV_LEN buffers, and plain read()/write() cut at 8192 bytes.
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

#include "i2c_dev.h"
#include "i2c_recorder.h"

namespace {

using tcs::I2cBus;
using tcs::I2cMessage;
using tcs::I2cResult;
using Bytes = std::vector<uint8_t>;

using Rig = RecorderRig;

void slave_addresses(void **)
{
	assert_int_equal(tcs::i2c_slave_check(0x7F, false), 0);
	assert_int_equal(tcs::i2c_slave_check(0x80, false), -EINVAL);
	assert_int_equal(tcs::i2c_slave_check(0x3FF, true), 0);
	assert_int_equal(tcs::i2c_slave_check(0x400, true), -EINVAL);
	assert_int_equal(tcs::i2c_slave_check(~0ul, true), -EINVAL);
}

void rdwr_refuses_before_the_bus(void **)
{
	Rig rig;
	std::vector<I2cMessage> m;
	I2cResult r = tcs::i2c_rdwr(rig.bus, m);
	assert_int_equal(r.error, -EINVAL);
	assert_int_equal(r.bits, 0);
	assert_false(r.note.empty());

	m.assign(42, I2cMessage{ 0x50, 0, { 1 } });
	r = tcs::i2c_rdwr(rig.bus, m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.done, 42);
	m.assign(43, I2cMessage{ 0x50, 0, { 1 } });
	assert_int_equal(tcs::i2c_rdwr(rig.bus, m).error, -EINVAL);

	rig.chip->log.clear();
	m = { { 0x50, 0, { 1 } }, { 0x50, I2C_M_RD, Bytes(8193) } };
	assert_int_equal(tcs::i2c_rdwr(rig.bus, m).error, -EINVAL);
	m = { { 0x50, 0, { 1 } }, { 0x50, I2C_M_RD, Bytes(8192) } };
	assert_int_equal(tcs::i2c_rdwr(rig.bus, m).error, 0);
	assert_int_equal(m[1].data.size(), 8192);
	// The refused transfer never reached the chip.
	assert_int_equal(rig.chip->log.rfind("Sw w01 Sr ", 0), 0);
}

void rdwr_recv_len_buffers(void **)
{
	Rig rig;
	// The first byte is how many bytes come besides the block; the
	// buffer must hold those and 32 more.
	Bytes buf(33, 0);
	buf[0] = 1;
	rig.chip->replies = { 2, 0x11, 0x22 };
	std::vector<I2cMessage> m = { { 0x50, 0, { 0x20 } }, { 0x50, I2C_M_RD | I2C_M_RECV_LEN, buf } };
	I2cResult r = tcs::i2c_rdwr(rig.bus, m);
	assert_int_equal(r.error, 0);
	assert_int_equal(r.done, 2);
	assert_true(m[1].data == (Bytes{ 2, 0x11, 0x22 }));

	// 2 extra bytes (a PEC): the count, the block and one more.
	buf.assign(34, 0);
	buf[0] = 2;
	rig.chip->replies = { 1, 0x33, 0x44 };
	m = { { 0x50, I2C_M_RD | I2C_M_RECV_LEN, buf } };
	assert_int_equal(tcs::i2c_rdwr(rig.bus, m).error, 0);
	assert_true(m[0].data == (Bytes{ 1, 0x33, 0x44 }));

	buf.assign(33, 0); // first byte 0
	m = { { 0x50, I2C_M_RD | I2C_M_RECV_LEN, buf } };
	assert_int_equal(tcs::i2c_rdwr(rig.bus, m).error, -EINVAL);
	buf.assign(32, 0); // too short for 1 + 32
	buf[0] = 1;
	m = { { 0x50, I2C_M_RD | I2C_M_RECV_LEN, buf } };
	assert_int_equal(tcs::i2c_rdwr(rig.bus, m).error, -EINVAL);
	m = { { 0x50, I2C_M_RD | I2C_M_RECV_LEN, {} } };
	assert_int_equal(tcs::i2c_rdwr(rig.bus, m).error, -EINVAL);
	buf.assign(33, 1); // not a read
	m = { { 0x50, I2C_M_RECV_LEN, buf } };
	assert_int_equal(tcs::i2c_rdwr(rig.bus, m).error, -EINVAL);
}

void rdwr_passes_the_bus_errors_on(void **)
{
	Rig rig;
	std::vector<I2cMessage> m = { { 0x50, 0, { 1 } }, { 0x22, I2C_M_RD, Bytes(1) } };
	const I2cResult r = tcs::i2c_rdwr(rig.bus, m);
	assert_int_equal(r.error, -ENXIO);
	assert_int_equal(r.done, 1);
	assert_int_equal(r.bits, 1 + 9 + 9 + 1 + 9 + 1);
}

void plain_read_and_write(void **)
{
	Rig rig;
	rig.chip->replies = { 7, 8 };
	Bytes out;
	I2cResult r = tcs::i2c_dev_read(rig.bus, 0x50, false, 2, out);
	assert_int_equal(r.error, 0);
	assert_true(out == (Bytes{ 7, 8 }));
	assert_int_equal(r.bits, 1 + 9 + 18 + 1);
	r = tcs::i2c_dev_write(rig.bus, 0x50, false, { 0xA0, 0xA1 });
	assert_int_equal(r.error, 0);
	assert_string_equal(rig.chip->log.c_str(), "Sr r r P Sw wa0 wa1 P ");

	// Cut at 8192 bytes, as i2c-dev cuts them.
	r = tcs::i2c_dev_read(rig.bus, 0x50, false, 10000, out);
	assert_int_equal(out.size(), 8192);
	assert_int_equal(r.bits, 1 + 9 + 8192 * 9 + 1);
	r = tcs::i2c_dev_write(rig.bus, 0x50, false, Bytes(9000, 0));
	assert_int_equal(r.bits, 1 + 9 + 8192 * 9 + 1);

	// Nothing there: -ENXIO, and out untouched.
	out = { 1 };
	assert_int_equal(tcs::i2c_dev_read(rig.bus, 0x51, false, 1, out).error, -ENXIO);
	assert_true(out == Bytes{ 1 });
	assert_int_equal(tcs::i2c_dev_write(rig.bus, 0x51, false, { 1 }).error, -ENXIO);
	// With I2C_TENBIT the address is a 10-bit one.
	assert_int_equal(tcs::i2c_dev_write(rig.bus, 0x50, true, { 1 }).error, -ENXIO);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(slave_addresses),
		cmocka_unit_test(rdwr_refuses_before_the_bus),
		cmocka_unit_test(rdwr_recv_len_buffers),
		cmocka_unit_test(rdwr_passes_the_bus_errors_on),
		cmocka_unit_test(plain_read_and_write),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
