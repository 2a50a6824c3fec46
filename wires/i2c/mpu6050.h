// An InvenSense MPU-6050 accelerometer and gyroscope as an I2C chip, at
// 0x68 or 0x69: its 128 8-bit registers (mpu6050_registers.h names the
// document they come from) and its I2C protocol, with the readings the
// caller gives it.
//
// The registers: reset values 0 but PWR_MGMT_1 0x40 (asleep) and WHO_AM_I
// 0x68; the documented read/write registers keep what is written, the
// read-only ones and those the document leaves out ignore writes and read
// their reset value. The first byte written after a START sets the
// register pointer (its low 7 bits); further bytes written are stored at,
// and bytes read come from, the pointer, which then moves on (0x7F wraps
// to 0x00), but for FIFO_R_W, where it stays, as FIFO reads expect.
// DEVICE_RESET (PWR_MGMT_1 bit 7) restores every register's reset value;
// USER_CTRL's reset bits clear themselves, SIG_COND_RESET zeroing the data
// registers. INT_STATUS's DATA_RDY_INT (bit 0) is set by a sample when
// INT_ENABLE's DATA_RDY_EN is, and cleared when INT_STATUS is read (by any
// read with INT_PIN_CFG's INT_RD_CLEAR).
//
// Data registers: ACCEL 0x3B..0x40, TEMP 0x41..0x42, GYRO 0x43..0x48,
// big-endian int16: accel·AFS LSB/g (16384, 8192, 4096, 2048 for ±2, 4, 8,
// 16 g, g = 9.80665 m/s²), gyro·FS LSB/(°/s) (131, 65.5, 32.8, 16.4 for
// ±250, 500, 1000, 2000 °/s), temperature (T − 36.53)·340; rounded to the
// nearest, saturated at −32768 and 32767, NaN as 0. Asleep (SLEEP, or
// CLKSEL 7: the clock stopped) a sample changes nothing: the registers
// keep their last values (0 after a reset); so does an axis in standby
// (PWR_MGMT_2) and the temperature with TEMP_DIS.
//
// Not emulated: the FIFO (FIFO_COUNT and FIFO_R_W read 0), the DMP, the
// auxiliary I2C master (EXT_SENS_DATA read 0), the INT pin, self-test,
// the low-pass filter (the readings are the caller's, filtered or not),
// CYCLE's low-power wake-ups (a sample is taken whenever given).
#pragma once

#include <cstdint>

#include "i2c_bus.h"

namespace tcs {

struct ImuReading {
	double accel[3] = { 0, 0, 0 }; // m/s²: specific force in the sensor frame (+g up at rest)
	double gyro[3] = { 0, 0, 0 };  // rad/s, in the sensor frame
	double temp_c = 25;
};

class Mpu6050 : public I2cChip {
public:
	Mpu6050();
	void start(bool read) override;
	bool write(uint8_t byte) override;
	uint8_t read() override;
	void stop() override;

	// A new sample into the data registers (when awake), at the sample
	// rate the caller keeps (sample_period_ns()).
	void sample(const ImuReading &reading);
	// Awake, with its clock running: samples change the data registers.
	bool sampling() const;
	// 1 / the sample rate: the gyroscope's output rate (8 kHz, 1 kHz with
	// the low-pass filter on: DLPF_CFG 1 to 6) / (1 + SMPLRT_DIV).
	int64_t sample_period_ns() const;
	// A register's value, without a read's side effects.
	uint8_t peek(uint8_t reg) const;

private:
	void reset();
	void store(uint8_t reg, uint8_t value);
	void put16(uint8_t reg, double value);
	uint8_t regs_[128];
	uint8_t pointer_ = 0;
	bool pointer_next_ = false; // the next byte written sets the pointer
};

} // namespace tcs
