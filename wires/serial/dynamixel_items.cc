// The XM430-W350's control table items and the values each may take (see
// dynamixel_items.h). Figures from the e-Manual's XM430-W350 page and the
// control table sections it includes.
#include "dynamixel_items.h"
#include "dynamixel2_packet.h"

namespace tcs {

namespace {

constexpr bool R = false, RW = true;
constexpr bool U = false, S = true;

// Fixed items, by address. (The Indirect ones are computed.)
constexpr DxlItem kItems[] = {
	{ kDxlModelNumber, 2, R, U, 0, 0, kDxlXm430W350, "Model Number" },
	{ kDxlModelInformation, 4, R, U, 0, 0, 0, "Model Information" },
	{ kDxlFirmwareVersion, 1, R, U, 0, 0, kDxlFirmware, "Firmware Version" },
	{ kDxlId, 1, RW, U, 0, 252, 1, "ID" },
	{ kDxlBaudRate, 1, RW, U, 0, 7, 1, "Baud Rate" },
	{ kDxlReturnDelayTime, 1, RW, U, 0, 254, 250, "Return Delay Time" },
	{ kDxlDriveMode, 1, RW, U, 0, 255, 0, "Drive Mode" },
	{ kDxlOperatingMode, 1, RW, U, 0, 255, kDxlPositionMode, "Operating Mode" },
	{ kDxlSecondaryId, 1, RW, U, 0, 255, 255, "Secondary ID" },
	{ kDxlProtocolType, 1, RW, U, 1, 2, 2, "Protocol Type" },
	{ kDxlHomingOffset, 4, RW, S, -1044479, 1044479, 0, "Homing Offset" },
	{ kDxlMovingThreshold, 4, RW, U, 0, 1023, 10, "Moving Threshold" },
	{ kDxlTemperatureLimit, 1, RW, U, 0, 100, 80, "Temperature Limit" },
	{ kDxlMaxVoltageLimit, 2, RW, U, 95, 160, 160, "Max Voltage Limit" },
	{ kDxlMinVoltageLimit, 2, RW, U, 95, 160, 95, "Min Voltage Limit" },
	{ kDxlPwmLimit, 2, RW, U, 0, 885, 885, "PWM Limit" },
	{ kDxlCurrentLimit, 2, RW, U, 0, 1193, 1193, "Current Limit" },
	{ kDxlAccelerationLimit, 4, RW, U, 0, 32767, 32767, "Acceleration Limit" },
	{ kDxlVelocityLimit, 4, RW, U, 0, 1023, 350, "Velocity Limit" },
	{ kDxlMaxPositionLimit, 4, RW, U, 0, 4095, 4095, "Max Position Limit" },
	{ kDxlMinPositionLimit, 4, RW, U, 0, 4095, 0, "Min Position Limit" },
	{ kDxlShutdown, 1, RW, U, 0, 255, 52, "Shutdown" },
	{ kDxlTorqueEnable, 1, RW, U, 0, 1, 0, "Torque Enable" },
	{ kDxlLed, 1, RW, U, 0, 1, 0, "LED" },
	{ kDxlStatusReturnLevel, 1, RW, U, 0, 2, 2, "Status Return Level" },
	{ kDxlRegisteredInstruction, 1, R, U, 0, 0, 0, "Registered Instruction" },
	{ kDxlHardwareErrorStatus, 1, R, U, 0, 0, 0, "Hardware Error Status" },
	{ kDxlVelocityIGain, 2, RW, U, 0, 16383, 1920, "Velocity I Gain" },
	{ kDxlVelocityPGain, 2, RW, U, 0, 16383, 100, "Velocity P Gain" },
	{ kDxlPositionDGain, 2, RW, U, 0, 16383, 0, "Position D Gain" },
	{ kDxlPositionIGain, 2, RW, U, 0, 16383, 0, "Position I Gain" },
	{ kDxlPositionPGain, 2, RW, U, 0, 16383, 800, "Position P Gain" },
	{ kDxlFeedforward2ndGain, 2, RW, U, 0, 16383, 0, "Feedforward 2nd Gain" },
	{ kDxlFeedforward1stGain, 2, RW, U, 0, 16383, 0, "Feedforward 1st Gain" },
	{ kDxlBusWatchdog, 1, RW, S, 0, 127, 0, "Bus Watchdog" },
	{ kDxlGoalPwm, 2, RW, S, -885, 885, 885, "Goal PWM" },
	{ kDxlGoalCurrent, 2, RW, S, -1193, 1193, 1193, "Goal Current" },
	{ kDxlGoalVelocity, 4, RW, S, -1023, 1023, 0, "Goal Velocity" },
	{ kDxlProfileAcceleration, 4, RW, U, 0, 32767, 0, "Profile Acceleration" },
	{ kDxlProfileVelocity, 4, RW, U, 0, 32767, 0, "Profile Velocity" },
	{ kDxlGoalPosition, 4, RW, S, -1048575, 1048575, 0, "Goal Position" },
	{ kDxlRealtimeTick, 2, R, U, 0, 0, 0, "Realtime Tick" },
	{ kDxlMoving, 1, R, U, 0, 0, 0, "Moving" },
	{ kDxlMovingStatus, 1, R, U, 0, 0, 0, "Moving Status" },
	{ kDxlPresentPwm, 2, R, S, 0, 0, 0, "Present PWM" },
	{ kDxlPresentCurrent, 2, R, S, 0, 0, 0, "Present Current" },
	{ kDxlPresentVelocity, 4, R, S, 0, 0, 0, "Present Velocity" },
	{ kDxlPresentPosition, 4, R, S, 0, 0, 0, "Present Position" },
	{ kDxlVelocityTrajectory, 4, R, S, 0, 0, 0, "Velocity Trajectory" },
	{ kDxlPositionTrajectory, 4, R, S, 0, 0, 0, "Position Trajectory" },
	{ kDxlPresentInputVoltage, 2, R, U, 0, 0, 120, "Present Input Voltage" },
	{ kDxlPresentTemperature, 1, R, U, 0, 0, 40, "Present Temperature" },
};

// Which bits of Drive Mode(10) and Shutdown(63) an XM430 has ("Unused,
// always 0" for the others): reverse, time-based profile, torque on by
// goal update; input voltage, overheating, encoder, shock, overload.
constexpr int64_t kDriveModeBits = 0x0D;
constexpr int64_t kShutdownBits = 0x3D;

uint8_t out_of(const DxlItem &it, int64_t v, std::string *why, const std::string &what)
{
	if (why)
		*why = std::string(it.name) + " (" + std::to_string(it.addr) + ") = " + std::to_string(v) + ": " + what;
	return kDxlDataRangeError;
}

uint8_t past_limit(const DxlItem &it, int64_t v, std::string *why, const std::string &what)
{
	out_of(it, v, why, what);
	return kDxlDataLimitError;
}

int64_t item_value(const uint8_t *table, uint16_t addr)
{
	return dxl_value(table, *dxl_item(addr));
}

} // namespace

std::optional<DxlItem> dxl_item(uint16_t addr)
{
	for (const DxlItem &it : kItems) {
		if (addr < it.addr)
			break;
		if (addr < it.addr + it.size)
			return it;
	}
	for (uint16_t base : { kDxlIndirectAddress1, kDxlIndirectAddress29 }) {
		const uint16_t data = base == kDxlIndirectAddress1 ? kDxlIndirectData1 : kDxlIndirectData29;
		if (addr >= base && addr < base + 2 * kDxlIndirectPerBlock) {
			const uint16_t at = uint16_t(addr - (addr - base) % 2);
			// By default each points at its own Indirect Data: plain storage.
			return DxlItem{ at,
					2,
					RW,
					U,
					kDxlRamStart,
					kDxlTableBytes - 1,
					data + (at - base) / 2,
					"Indirect Address" };
		}
		if (addr >= data && addr < data + kDxlIndirectPerBlock)
			return DxlItem{ addr, 1, RW, U, 0, 255, 0, "Indirect Data" };
	}
	return std::nullopt;
}

std::optional<uint16_t> dxl_indirect_address_of(uint16_t addr)
{
	if (addr >= kDxlIndirectData1 && addr < kDxlIndirectData1 + kDxlIndirectPerBlock)
		return uint16_t(kDxlIndirectAddress1 + 2 * (addr - kDxlIndirectData1));
	if (addr >= kDxlIndirectData29 && addr < kDxlIndirectData29 + kDxlIndirectPerBlock)
		return uint16_t(kDxlIndirectAddress29 + 2 * (addr - kDxlIndirectData29));
	return std::nullopt;
}

int64_t dxl_value(const uint8_t *table, const DxlItem &it)
{
	uint64_t u = 0;
	for (int i = 0; i < it.size; i++)
		u |= uint64_t(table[it.addr + i]) << (8 * i);
	if (it.is_signed && it.size < 8 && (u >> (8 * it.size - 1)) & 1)
		u |= ~uint64_t(0) << (8 * it.size);
	return (int64_t)u;
}

uint8_t dxl_check_value(const DxlItem &it, const uint8_t *table, std::string *why)
{
	const int64_t v = dxl_value(table, it);
	const bool goal = it.addr == kDxlGoalPwm || it.addr == kDxlGoalCurrent || it.addr == kDxlGoalVelocity ||
			  it.addr == kDxlGoalPosition;
	if (goal && item_value(table, kDxlBusWatchdog) == -1)
		return out_of(it, v, why, "goals are read-only while the Bus Watchdog has tripped");
	switch (it.addr) {
	case kDxlDriveMode:
		if (v & ~kDriveModeBits)
			return out_of(it, v, why, "sets a bit the XM430 does not use");
		return 0;
	case kDxlShutdown:
		if (v & ~kShutdownBits)
			return out_of(it, v, why, "sets a bit the XM430 does not use");
		return 0;
	case kDxlOperatingMode:
		if (v != kDxlCurrentMode && v != kDxlVelocityMode && v != kDxlPositionMode &&
		    v != kDxlExtendedPositionMode && v != kDxlCurrentPositionMode && v != kDxlPwmMode)
			return out_of(it, v, why, "no such mode (0, 1, 3, 4, 5, 16)");
		return 0;
	default:
		break;
	}
	if (v < it.min || v > it.max)
		return out_of(it, v, why, "outside " + std::to_string(it.min) + " to " + std::to_string(it.max));
	// The limits a goal may not pass.
	auto within = [&](uint16_t limit_addr, const char *limit) -> uint8_t {
		const int64_t lim = item_value(table, limit_addr);
		if (v > lim || v < -lim)
			return past_limit(it, v, why, std::string("beyond ") + limit + " " + std::to_string(lim));
		return 0;
	};
	switch (it.addr) {
	case kDxlGoalPwm:
		return within(kDxlPwmLimit, "PWM Limit");
	case kDxlGoalCurrent:
		return within(kDxlCurrentLimit, "Current Limit");
	case kDxlGoalVelocity:
		return within(kDxlVelocityLimit, "Velocity Limit");
	case kDxlProfileAcceleration:
		return within(kDxlAccelerationLimit, "Acceleration Limit");
	case kDxlGoalPosition:
		if (item_value(table, kDxlOperatingMode) == kDxlPositionMode) {
			const int64_t lo = item_value(table, kDxlMinPositionLimit);
			const int64_t hi = item_value(table, kDxlMaxPositionLimit);
			if (v < lo || v > hi)
				return past_limit(it, v, why,
						  "outside the position limits " + std::to_string(lo) + " to " +
							  std::to_string(hi));
		}
		return 0;
	default:
		return 0;
	}
}

} // namespace tcs
