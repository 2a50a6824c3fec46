// Mpu6050: the register file, its I2C protocol and its samples (see mpu6050.h).
#include "mpu6050.h"

#include <cmath>
#include <cstring>
#include <numbers>

#include "mpu6050_registers.h"

namespace tcs {

using namespace mpu6050;

namespace {

// The registers the register map (rev. 4.2 section 3; MOT_THR 0x1F from
// rev. 4.0) calls R/W and that the model keeps. FIFO_COUNT and FIFO_R_W,
// R/W in the map, are the FIFO's, which is not emulated.
bool writable(uint8_t reg)
{
	return (reg >= kSelfTestX && reg <= 0x10) || (reg >= kSmplrtDiv && reg <= kAccelConfig) || reg == 0x1F ||
	       (reg >= kFifoEn && reg < kI2cSlv4Di) || reg == kIntPinCfg || reg == kIntEnable ||
	       (reg >= kI2cSlv0Do && reg <= kSignalPathReset) || reg == kUserCtrl || reg == kPwrMgmt1 ||
	       reg == kPwrMgmt2;
}

// A reading in LSB as the register's int16, big-endian halves apart.
uint16_t to_raw(double lsb)
{
	if (std::isnan(lsb))
		return 0;
	const double r = std::round(lsb);
	if (r >= 32767)
		return 0x7FFF;
	if (r <= -32768)
		return 0x8000;
	return uint16_t(int16_t(r));
}

} // namespace

Mpu6050::Mpu6050()
{
	reset();
}

void Mpu6050::reset()
{
	memset(regs_, 0, sizeof regs_);
	regs_[kPwrMgmt1] = kPwrMgmt1Reset;
	regs_[kWhoAmI] = kWhoAmIValue;
}

void Mpu6050::start(bool)
{
	pointer_next_ = true;
}

void Mpu6050::stop() {}

void Mpu6050::store(uint8_t reg, uint8_t value)
{
	if (!writable(reg))
		return;
	if (reg == kPwrMgmt1 && (value & kDeviceReset)) {
		reset();
		return;
	}
	if (reg == kUserCtrl) {
		if (value & kSigCondReset)
			memset(regs_ + kAccelXoutH, 0, kGyroXoutH + 6 - kAccelXoutH);
		value &= uint8_t(~kUserCtrlResets);
	}
	regs_[reg] = value;
}

bool Mpu6050::write(uint8_t byte)
{
	if (pointer_next_) {
		pointer_ = byte & 0x7F;
		pointer_next_ = false;
		return true;
	}
	store(pointer_, byte);
	if (pointer_ != kFifoRW)
		pointer_ = (pointer_ + 1) & 0x7F;
	return true;
}

uint8_t Mpu6050::read()
{
	const uint8_t value = regs_[pointer_];
	if (pointer_ == kIntStatus || (regs_[kIntPinCfg] & kIntRdClear))
		regs_[kIntStatus] = 0;
	if (pointer_ != kFifoRW)
		pointer_ = (pointer_ + 1) & 0x7F;
	return value;
}

uint8_t Mpu6050::peek(uint8_t reg) const
{
	return regs_[reg & 0x7F];
}

void Mpu6050::put16(uint8_t reg, double lsb)
{
	const uint16_t raw = to_raw(lsb);
	regs_[reg] = uint8_t(raw >> 8);
	regs_[reg + 1] = uint8_t(raw & 0xFF);
}

bool Mpu6050::sampling() const
{
	const uint8_t pm = regs_[kPwrMgmt1];
	return !(pm & kSleep) && (pm & kClkStop) != kClkStop;
}

int64_t Mpu6050::sample_period_ns() const
{
	const uint8_t dlpf = regs_[kConfig] & 7;
	const int64_t gyro_rate_period = dlpf == 0 || dlpf == 7 ? 125000 : 1000000; // 8 kHz, 1 kHz
	return gyro_rate_period * (1 + regs_[kSmplrtDiv]);
}

void Mpu6050::sample(const ImuReading &reading)
{
	if (!sampling())
		return;
	const int afs = regs_[kAccelConfig] >> 3 & 3, fs = regs_[kGyroConfig] >> 3 & 3;
	const double lsb_per_g = 16384 >> afs;
	static constexpr double kLsbPerDps[4] = { 131, 65.5, 32.8, 16.4 };
	const double lsb_per_rad = kLsbPerDps[fs] * 180 / std::numbers::pi;
	const uint8_t standby = regs_[kPwrMgmt2];
	for (int i = 0; i < 3; i++) {
		if (!(standby & (0x20 >> i)))
			put16(uint8_t(kAccelXoutH + 2 * i), reading.accel[i] / kStandardGravity * lsb_per_g);
		if (!(standby & (0x04 >> i)))
			put16(uint8_t(kGyroXoutH + 2 * i), reading.gyro[i] * lsb_per_rad);
	}
	if (!(regs_[kPwrMgmt1] & kTempDis))
		put16(kTempOutH, (reading.temp_c - 36.53) * 340);
	if (regs_[kIntEnable] & kDataRdy)
		regs_[kIntStatus] |= kDataRdy;
}

} // namespace tcs
