// The XM430-W350's control table as the ROBOTIS e-Manual gives it: each
// item's address, size, access, initial value and the values a WRITE may
// give it. Addresses 0-63 are the EEPROM area (locked while torque is on),
// 64 on the RAM area; the addresses between items hold nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace tcs {

constexpr uint16_t kDxlTableBytes = 662; // to Indirect Data 56 (661)
constexpr uint16_t kDxlRamStart = 64;

constexpr uint16_t kDxlXm430W350 = 1020; // Model Number
constexpr uint8_t kDxlFirmware = 46;     // Firmware Version: one with every item below

// EEPROM area.
constexpr uint16_t kDxlModelNumber = 0;
constexpr uint16_t kDxlModelInformation = 2;
constexpr uint16_t kDxlFirmwareVersion = 6;
constexpr uint16_t kDxlId = 7;
constexpr uint16_t kDxlBaudRate = 8;
constexpr uint16_t kDxlReturnDelayTime = 9;
constexpr uint16_t kDxlDriveMode = 10;
constexpr uint16_t kDxlOperatingMode = 11;
constexpr uint16_t kDxlSecondaryId = 12;
constexpr uint16_t kDxlProtocolType = 13;
constexpr uint16_t kDxlHomingOffset = 20;
constexpr uint16_t kDxlMovingThreshold = 24;
constexpr uint16_t kDxlTemperatureLimit = 31;
constexpr uint16_t kDxlMaxVoltageLimit = 32;
constexpr uint16_t kDxlMinVoltageLimit = 34;
constexpr uint16_t kDxlPwmLimit = 36;
constexpr uint16_t kDxlCurrentLimit = 38;
constexpr uint16_t kDxlAccelerationLimit = 40;
constexpr uint16_t kDxlVelocityLimit = 44;
constexpr uint16_t kDxlMaxPositionLimit = 48;
constexpr uint16_t kDxlMinPositionLimit = 52;
constexpr uint16_t kDxlShutdown = 63;
// RAM area.
constexpr uint16_t kDxlTorqueEnable = 64;
constexpr uint16_t kDxlLed = 65;
constexpr uint16_t kDxlStatusReturnLevel = 68;
constexpr uint16_t kDxlRegisteredInstruction = 69;
constexpr uint16_t kDxlHardwareErrorStatus = 70;
constexpr uint16_t kDxlVelocityIGain = 76;
constexpr uint16_t kDxlVelocityPGain = 78;
constexpr uint16_t kDxlPositionDGain = 80;
constexpr uint16_t kDxlPositionIGain = 82;
constexpr uint16_t kDxlPositionPGain = 84;
constexpr uint16_t kDxlFeedforward2ndGain = 88;
constexpr uint16_t kDxlFeedforward1stGain = 90;
constexpr uint16_t kDxlBusWatchdog = 98;
constexpr uint16_t kDxlGoalPwm = 100;
constexpr uint16_t kDxlGoalCurrent = 102;
constexpr uint16_t kDxlGoalVelocity = 104;
constexpr uint16_t kDxlProfileAcceleration = 108;
constexpr uint16_t kDxlProfileVelocity = 112;
constexpr uint16_t kDxlGoalPosition = 116;
constexpr uint16_t kDxlRealtimeTick = 120;
constexpr uint16_t kDxlMoving = 122;
constexpr uint16_t kDxlMovingStatus = 123;
constexpr uint16_t kDxlPresentPwm = 124;
constexpr uint16_t kDxlPresentCurrent = 126;
constexpr uint16_t kDxlPresentVelocity = 128;
constexpr uint16_t kDxlPresentPosition = 132;
constexpr uint16_t kDxlVelocityTrajectory = 136;
constexpr uint16_t kDxlPositionTrajectory = 140;
constexpr uint16_t kDxlPresentInputVoltage = 144;
constexpr uint16_t kDxlPresentTemperature = 146;
// Indirect Address n (2 bytes) and Indirect Data n (1 byte): n = 1-28 and 29-56.
constexpr uint16_t kDxlIndirectAddress1 = 168;
constexpr uint16_t kDxlIndirectData1 = 224;
constexpr uint16_t kDxlIndirectAddress29 = 578;
constexpr uint16_t kDxlIndirectData29 = 634;
constexpr int kDxlIndirectPerBlock = 28;

// Operating Mode values.
constexpr int kDxlCurrentMode = 0;
constexpr int kDxlVelocityMode = 1;
constexpr int kDxlPositionMode = 3;
constexpr int kDxlExtendedPositionMode = 4;
constexpr int kDxlCurrentPositionMode = 5;
constexpr int kDxlPwmMode = 16;

struct DxlItem {
	uint16_t addr;
	uint8_t size; // bytes, little-endian
	bool writable;
	bool is_signed;
	int64_t min, max; // what a WRITE may give (more checks: dxl_check_value)
	int64_t initial;  // at power-on and after a factory reset
	const char *name;
};

// The item holding address addr (at any of its bytes); none in a gap or
// past the table.
std::optional<DxlItem> dxl_item(uint16_t addr);

// Indirect Data at addr: the Indirect Address item that says where it
// points; none for any other address.
std::optional<uint16_t> dxl_indirect_address_of(uint16_t addr);

// The value of item `it` in the bytes of a table (kDxlTableBytes).
int64_t dxl_value(const uint8_t *table, const DxlItem &it);

// Whether a WRITE may leave item `it` as the table (after the write)
// holds it: 0, or the status error with why. Data Range Error: outside
// the item's own values; Data Limit Error: outside what a limit item (PWM,
// Current, Velocity, Acceleration, Position Limit) allows; as the
// e-Manual's "Bus Watchdog" says, a goal written while the watchdog has
// tripped is a Data Range Error.
uint8_t dxl_check_value(const DxlItem &it, const uint8_t *table, std::string *why);

} // namespace tcs
