// Mpu6050 (wires/i2c/mpu6050.h) on a bus at 400 kHz, through the calls a
// controller makes (I2C_SMBUS, I2C_RDWR, read/write): WHO_AM_I, asleep
// after reset, the data registers of a known sample at each full-scale
// range worked out by hand from the register map's sensitivities,
// saturation, reset, INT_STATUS and the register pointer.
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <numbers>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "i2c_dev.h"
#include "mpu6050.h"
#include "mpu6050_registers.h"
#include "smbus.h"

namespace {

using tcs::I2cMessage;
using tcs::ImuReading;
using Bytes = std::vector<uint8_t>;

constexpr double g = 9.80665;

double rad(double dps)
{
	return dps * std::numbers::pi / 180;
}

struct Rig {
	Rig() : bus(400000)
	{
		auto c = std::make_unique<tcs::Mpu6050>();
		imu = c.get();
		assert_true(bus.attach(0x68, std::move(c)).ok());
	}
	uint8_t get(uint8_t reg)
	{
		i2c_smbus_data d;
		memset(&d, 0, sizeof d);
		const tcs::SmbusResult r =
			tcs::i2c_smbus(bus, 0x68, false, I2C_SMBUS_READ, reg, I2C_SMBUS_BYTE_DATA, &d);
		assert_int_equal(r.xfer.error, 0);
		return d.byte;
	}
	void set(uint8_t reg, uint8_t value)
	{
		i2c_smbus_data d;
		d.byte = value;
		assert_int_equal(
			tcs::i2c_smbus(bus, 0x68, false, I2C_SMBUS_WRITE, reg, I2C_SMBUS_BYTE_DATA, &d).xfer.error, 0);
	}
	// ACCEL, TEMP and GYRO in one burst, as I2C_RDWR does it.
	Bytes burst(int64_t *ns = nullptr)
	{
		std::vector<I2cMessage> m = { { 0x68, 0, { 0x3B } }, { 0x68, I2C_M_RD, Bytes(14) } };
		const tcs::I2cResult r = tcs::i2c_rdwr(bus, m);
		assert_int_equal(r.error, 0);
		assert_int_equal(r.done, 2);
		if (ns)
			*ns = r.wire_ns;
		return m[1].data;
	}
	tcs::I2cBus bus;
	tcs::Mpu6050 *imu;
};

// Accel 0.5 g, -0.25 g, 1 g; gyro 100, -30, 250 °/s; 25 °C.
ImuReading known_sample()
{
	ImuReading s;
	s.accel[0] = 0.5 * g;
	s.accel[1] = -0.25 * g;
	s.accel[2] = g;
	s.gyro[0] = rad(100);
	s.gyro[1] = rad(-30);
	s.gyro[2] = rad(250);
	s.temp_c = 25;
	return s;
}

void who_am_i_through_read_byte_data(void **)
{
	Rig rig;
	i2c_smbus_data d;
	memset(&d, 0, sizeof d);
	const tcs::SmbusResult r = tcs::i2c_smbus(rig.bus, 0x68, false, I2C_SMBUS_READ, 0x75, I2C_SMBUS_BYTE_DATA, &d);
	assert_int_equal(r.xfer.error, 0);
	assert_int_equal(d.byte, 0x68);
	assert_int_equal(r.xfer.wire_ns, 97500); // 39 bits of 2.5 µs
	// Nothing at 0x69 (AD0 low).
	assert_int_equal(
		tcs::i2c_smbus(rig.bus, 0x69, false, I2C_SMBUS_READ, 0x75, I2C_SMBUS_BYTE_DATA, &d).xfer.error, -ENXIO);
}

void reset_values(void **)
{
	tcs::Mpu6050 imu;
	for (int reg = 0; reg < 128; reg++)
		assert_int_equal(imu.peek(uint8_t(reg)), reg == 0x6B ? 0x40 : reg == 0x75 ? 0x68 : 0);
}

void asleep_after_reset_then_woken(void **)
{
	Rig rig;
	assert_false(rig.imu->sampling());
	rig.imu->sample(known_sample());
	assert_true(rig.burst() == Bytes(14, 0));
	rig.set(0x6B, 0x00); // SLEEP cleared
	assert_true(rig.imu->sampling());
	rig.imu->sample(known_sample());
	assert_true(rig.burst() != Bytes(14, 0));
	// Asleep again, the registers keep the last sample.
	const Bytes last = rig.burst();
	rig.set(0x6B, 0x40);
	ImuReading other = known_sample();
	other.accel[0] = -g;
	rig.imu->sample(other);
	assert_true(rig.burst() == last);
	// CLKSEL 7 stops the clock: no samples either.
	rig.set(0x6B, 0x07);
	assert_false(rig.imu->sampling());
}

void a_burst_at_each_full_scale_range(void **)
{
	// Raw = value · LSB per unit, rounded: accel 16384/8192/4096/2048 LSB/g,
	// gyro 131/65.5/32.8/16.4 LSB/(°/s), temp (25 − 36.53)·340 = −3920.2 →
	// −3920 = 0xF0B0; big-endian, ACCEL X Y Z, TEMP, GYRO X Y Z.
	const uint8_t want[4][14] = {
		// 8192, -4096, 16384; 13100, -3930, 32750
		{ 0x20, 0x00, 0xF0, 0x00, 0x40, 0x00, 0xF0, 0xB0, 0x33, 0x2C, 0xF0, 0xA6, 0x7F, 0xEE },
		// 4096, -2048, 8192; 6550, -1965, 16375
		{ 0x10, 0x00, 0xF8, 0x00, 0x20, 0x00, 0xF0, 0xB0, 0x19, 0x96, 0xF8, 0x53, 0x3F, 0xF7 },
		// 2048, -1024, 4096; 3280, -984, 8200
		{ 0x08, 0x00, 0xFC, 0x00, 0x10, 0x00, 0xF0, 0xB0, 0x0C, 0xD0, 0xFC, 0x28, 0x20, 0x08 },
		// 1024, -512, 2048; 1640, -492, 4100
		{ 0x04, 0x00, 0xFE, 0x00, 0x08, 0x00, 0xF0, 0xB0, 0x06, 0x68, 0xFE, 0x14, 0x10, 0x04 },
	};
	for (int range = 0; range < 4; range++) {
		Rig rig;
		rig.set(0x6B, 0x01); // awake, PLL on the X gyro
		rig.set(0x1C, uint8_t(range << 3));
		rig.set(0x1B, uint8_t(range << 3));
		rig.imu->sample(known_sample());
		int64_t ns = 0;
		const Bytes got = rig.burst(&ns);
		assert_memory_equal(got.data(), want[range], 14);
		// S + addr + 0x3B + Sr + addr + 14 bytes + P = 156 bits at 400 kHz.
		assert_int_equal(ns, 390000);
	}
}

void readings_saturate(void **)
{
	Rig rig;
	rig.set(0x6B, 0x00);
	ImuReading s;
	s.accel[0] = 3 * g; // past ±2 g
	s.accel[1] = -3 * g;
	s.accel[2] = NAN;
	s.gyro[0] = rad(300); // past ±250 °/s
	s.gyro[1] = -INFINITY;
	s.gyro[2] = rad(250.1); // 32763.1: still inside
	s.temp_c = 1000;
	rig.imu->sample(s);
	const Bytes want = { 0x7F, 0xFF, 0x80, 0x00, 0x00, 0x00, 0x7F, 0xFF, 0x7F, 0xFF, 0x80, 0x00, 0x7F, 0xFB };
	assert_true(rig.burst() == want);
}

void device_reset_restores_everything(void **)
{
	Rig rig;
	rig.set(0x6B, 0x00);
	rig.set(0x19, 7);
	rig.set(0x1B, 0x18);
	rig.set(0x38, 0x01);
	rig.imu->sample(known_sample());
	assert_int_equal(rig.get(0x19), 7);
	rig.set(0x6B, 0x80); // DEVICE_RESET
	for (int reg = 0; reg < 128; reg++)
		assert_int_equal(rig.imu->peek(uint8_t(reg)), reg == 0x6B ? 0x40 : reg == 0x75 ? 0x68 : 0);
	assert_false(rig.imu->sampling());
}

void read_only_registers_ignore_writes(void **)
{
	Rig rig;
	rig.set(0x75, 0x00);
	assert_int_equal(rig.get(0x75), 0x68);
	rig.set(0x3B, 0x55);
	assert_int_equal(rig.get(0x3B), 0);
	rig.set(0x72, 0x12); // FIFO_COUNT: no FIFO
	assert_int_equal(rig.get(0x72), 0);
	rig.set(0x00, 0x12); // not in the register map
	assert_int_equal(rig.get(0x00), 0);
	rig.set(0x1A, 0x03); // CONFIG is R/W
	assert_int_equal(rig.get(0x1A), 0x03);
}

void a_burst_write_and_the_sample_rate(void **)
{
	Rig rig;
	// The pointer, then bytes at 0x19, 0x1A, 0x1B, 0x1C.
	std::vector<uint8_t> bytes = { 0x19, 7, 3, 0x08, 0x10 };
	assert_int_equal(tcs::i2c_dev_write(rig.bus, 0x68, false, bytes).error, 0);
	assert_int_equal(rig.imu->peek(0x19), 7);
	assert_int_equal(rig.imu->peek(0x1A), 3);
	assert_int_equal(rig.imu->peek(0x1B), 0x08);
	assert_int_equal(rig.imu->peek(0x1C), 0x10);
	// DLPF on: 1 kHz / (1 + 7) = 125 Hz, 8 ms.
	assert_int_equal(rig.imu->sample_period_ns(), 8000000);
	// DLPF off: 8 kHz / (1 + 7) = 1 kHz.
	rig.set(0x1A, 0);
	assert_int_equal(rig.imu->sample_period_ns(), 1000000);
	rig.set(0x19, 0);
	assert_int_equal(rig.imu->sample_period_ns(), 125000);
	rig.set(0x1A, 7); // DLPF_CFG 7: off as well
	rig.set(0x19, 4);
	assert_int_equal(rig.imu->sample_period_ns(), 625000);
}

void data_ready_is_cleared_by_reading_it(void **)
{
	Rig rig;
	rig.set(0x6B, 0x00);
	rig.imu->sample(known_sample());
	assert_int_equal(rig.get(0x3A), 0); // DATA_RDY_EN off
	rig.set(0x38, 0x01);
	rig.imu->sample(known_sample());
	rig.get(0x3B); // another register leaves it
	assert_int_equal(rig.get(0x3A), 0x01);
	assert_int_equal(rig.get(0x3A), 0x00);
	// INT_RD_CLEAR: any read clears it.
	rig.set(0x37, 0x10);
	rig.imu->sample(known_sample());
	rig.get(0x3B);
	assert_int_equal(rig.get(0x3A), 0x00);
}

void the_pointer_outlives_the_transfer(void **)
{
	Rig rig;
	assert_int_equal(tcs::i2c_dev_write(rig.bus, 0x68, false, { 0x75 }).error, 0);
	Bytes out;
	assert_int_equal(tcs::i2c_dev_read(rig.bus, 0x68, false, 1, out).error, 0);
	assert_true(out == Bytes{ 0x68 });
	// Reading moves it on: 0x76 reads 0.
	assert_int_equal(tcs::i2c_dev_read(rig.bus, 0x68, false, 1, out).error, 0);
	assert_true(out == Bytes{ 0x00 });
	// At FIFO_R_W it stays, for FIFO bursts: not on to WHO_AM_I.
	assert_int_equal(tcs::i2c_dev_write(rig.bus, 0x68, false, { 0x74 }).error, 0);
	assert_int_equal(tcs::i2c_dev_read(rig.bus, 0x68, false, 2, out).error, 0);
	assert_true(out == (Bytes{ 0x00, 0x00 }));
	// 0x7F wraps to 0x00: 109 bytes from 0x7F are 0x7F, 0x00, ... 0x6B.
	assert_int_equal(tcs::i2c_dev_write(rig.bus, 0x68, false, { 0x7F }).error, 0);
	assert_int_equal(tcs::i2c_dev_read(rig.bus, 0x68, false, 109, out).error, 0);
	assert_int_equal(out.size(), 109);
	assert_int_equal(out[108], 0x40);
	// A pointer byte's low 7 bits: 0xF5 is 0x75.
	assert_int_equal(tcs::i2c_dev_write(rig.bus, 0x68, false, { 0xF5 }).error, 0);
	assert_int_equal(tcs::i2c_dev_read(rig.bus, 0x68, false, 1, out).error, 0);
	assert_true(out == Bytes{ 0x68 });
}

void standby_axes_and_temp_dis_keep_their_values(void **)
{
	Rig rig;
	rig.set(0x6B, 0x00);
	rig.imu->sample(known_sample());
	rig.set(0x6C, 0x24); // STBY_XA, STBY_XG
	rig.set(0x6B, 0x08); // TEMP_DIS
	ImuReading s;	     // all 0, 25 °C
	s.temp_c = 40;
	rig.imu->sample(s);
	const Bytes want = { 0x20, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF0, 0xB0, 0x33, 0x2C, 0x00, 0x00, 0x00, 0x00 };
	assert_true(rig.burst() == want);
}

void sig_cond_reset_clears_the_data(void **)
{
	Rig rig;
	rig.set(0x6B, 0x00);
	rig.imu->sample(known_sample());
	rig.set(0x6A, 0x41); // FIFO_EN and SIG_COND_RESET
	assert_true(rig.burst() == Bytes(14, 0));
	assert_int_equal(rig.get(0x6A), 0x40); // the reset bit cleared itself
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(who_am_i_through_read_byte_data),
		cmocka_unit_test(reset_values),
		cmocka_unit_test(asleep_after_reset_then_woken),
		cmocka_unit_test(a_burst_at_each_full_scale_range),
		cmocka_unit_test(readings_saturate),
		cmocka_unit_test(device_reset_restores_everything),
		cmocka_unit_test(read_only_registers_ignore_writes),
		cmocka_unit_test(a_burst_write_and_the_sample_rate),
		cmocka_unit_test(data_ready_is_cleared_by_reading_it),
		cmocka_unit_test(the_pointer_outlives_the_transfer),
		cmocka_unit_test(standby_axes_and_temp_dis_keep_their_values),
		cmocka_unit_test(sig_cond_reset_clears_the_data),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
