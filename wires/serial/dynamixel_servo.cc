// DynamixelServo: executing an instruction and answering it (see
// dynamixel_servo.h).
#include "dynamixel_servo.h"

#include <algorithm>

namespace tcs {

namespace {

constexpr uint8_t kClearMagic[5] = { 0x01, 0x44, 0x58, 0x4C, 0x22 };

DxlAnswer refused(uint8_t error, const std::string &note)
{
	DxlAnswer a;
	a.error = error;
	a.note = note;
	return a;
}

uint16_t le16(const uint8_t *p)
{
	return uint16_t(p[0] | p[1] << 8);
}

} // namespace

DynamixelServo::DynamixelServo(uint8_t id)
{
	table_.set(kDxlId, std::min<uint8_t>(id, kDxlMaxId));
}

int DynamixelServo::secondary_id() const
{
	const int64_t s = table_.get(kDxlSecondaryId);
	return s <= kDxlMaxId ? int(s) : -1;
}

int64_t DynamixelServo::baud() const
{
	static constexpr int64_t kRates[] = { 9600, 57600, 115200, 1000000, 2000000, 3000000, 4000000, 4500000 };
	const int64_t v = table_.get(kDxlBaudRate);
	return v >= 0 && v < 8 ? kRates[v] : kRates[1];
}

bool DynamixelServo::answers(uint8_t instruction) const
{
	const int64_t level = table_.get(kDxlStatusReturnLevel);
	if (instruction == kDxlPing)
		return true;
	if (instruction == kDxlRead || instruction == kDxlSyncRead || instruction == kDxlBulkRead)
		return level >= 1;
	return level >= 2;
}

DxlAnswer DynamixelServo::execute(const Dxl2Packet &p, DxlAddressing how)
{
	// Decided before executing: a REBOOT or a WRITE to Status Return
	// Level(68) answers at the level the packet found.
	const bool answer = how == DxlAddressing::id ? answers(p.instruction)
						     : how == DxlAddressing::broadcast && p.instruction == kDxlPing;
	DxlAnswer a;
	switch (p.instruction) {
	case kDxlPing:
		a = ping();
		break;
	case kDxlRead:
		if (p.params.size() != 4)
			a = refused(kDxlDataLengthError,
				    "READ with " + std::to_string(p.params.size()) + " params (address and length: 4)");
		else if (how == DxlAddressing::id)
			a = read(le16(p.params.data()), le16(p.params.data() + 2));
		break;
	case kDxlWrite:
		if (p.params.size() < 3)
			a = refused(kDxlDataLengthError, "WRITE with " + std::to_string(p.params.size()) +
								 " params (an address and data: 3 or more)");
		else
			a = write(le16(p.params.data()), p.params.data() + 2, p.params.size() - 2, how);
		break;
	case kDxlRegWrite:
		a = reg_write(p, how);
		break;
	case kDxlAction:
		a = action();
		break;
	case kDxlFactoryReset:
		a = factory_reset(p, how);
		break;
	case kDxlReboot:
		a = reboot();
		break;
	case kDxlClear:
		a = clear(p);
		break;
	case kDxlStatus:
		return a; // another device's answer
	case kDxlSyncRead:
	case kDxlSyncWrite:
	case kDxlBulkRead:
	case kDxlBulkWrite:
		a = refused(kDxlInstructionError, "SYNC/BULK instruction " + std::to_string(p.instruction) +
							  " sent to one ID, not the broadcast ID");
		break;
	default:
		a = refused(kDxlInstructionError, "no instruction " + std::to_string(p.instruction));
		break;
	}
	a.sent = answer;
	if (!answer)
		a.params.clear();
	return a;
}

DxlAnswer DynamixelServo::ping() const
{
	DxlAnswer a;
	const int64_t model = table_.get(kDxlModelNumber);
	a.params = { uint8_t(model), uint8_t(model >> 8), uint8_t(table_.get(kDxlFirmwareVersion)) };
	return a;
}

DxlAnswer DynamixelServo::read(uint16_t addr, size_t n) const
{
	DxlAnswer a;
	std::string why;
	a.error = table_.read(addr, n, a.params, &why);
	if (a.error) {
		a.params.clear();
		a.note = "READ refused: " + why;
	}
	return a;
}

DxlAnswer DynamixelServo::write(uint16_t addr, const uint8_t *data, size_t n, DxlAddressing how)
{
	DxlControlTable::Staged s;
	std::string why;
	if (const uint8_t e = table_.stage(addr, data, n, how == DxlAddressing::secondary, s, &why))
		return refused(e, "WRITE refused: " + why);
	const int64_t torque = table_.get(kDxlTorqueEnable), mode = table_.get(kDxlOperatingMode);
	table_.commit(s);
	written(s, torque, mode);
	return {};
}

void DynamixelServo::written(const DxlControlTable::Staged &s, int64_t torque_before, int64_t mode_before)
{
	for (uint16_t item : s.items) {
		if (item == kDxlOperatingMode && table_.get(kDxlOperatingMode) != mode_before)
			drive_.mode_changed(table_);
		else if (item == kDxlTorqueEnable && torque_before == 0 && table_.get(kDxlTorqueEnable) == 1)
			drive_.torque_on(table_);
		else if (item == kDxlGoalPosition)
			drive_.goal_written(table_);
	}
}

DxlAnswer DynamixelServo::reg_write(const Dxl2Packet &p, DxlAddressing how)
{
	if (p.params.size() < 3)
		return refused(kDxlDataLengthError, "REG_WRITE with " + std::to_string(p.params.size()) +
							    " params (an address and data: 3 or more)");
	DxlControlTable::Staged s;
	std::string why;
	if (const uint8_t e = table_.stage(le16(p.params.data()), p.params.data() + 2, p.params.size() - 2,
					   how == DxlAddressing::secondary, s, &why))
		return refused(e, "REG_WRITE refused: " + why);
	registered_ = p.params;
	table_.set(kDxlRegisteredInstruction, 1);
	return {};
}

DxlAnswer DynamixelServo::action()
{
	if (table_.get(kDxlRegisteredInstruction) == 0)
		return refused(kDxlInstructionError, "ACTION with no REG_WRITE registered");
	table_.set(kDxlRegisteredInstruction, 0);
	const std::vector<uint8_t> w = std::move(registered_);
	registered_.clear();
	// Checked again: the table may have changed since.
	DxlAnswer a = write(le16(w.data()), w.data() + 2, w.size() - 2, DxlAddressing::id);
	if (a.error)
		a.note = "ACTION: " + a.note;
	return a;
}

DxlAnswer DynamixelServo::factory_reset(const Dxl2Packet &p, DxlAddressing how)
{
	if (p.params.size() != 1)
		return refused(kDxlDataLengthError,
			       "FACTORY_RESET with " + std::to_string(p.params.size()) + " params (an option: 1)");
	const uint8_t option = p.params[0];
	if (option != 0xFF && option != 0x01 && option != 0x02)
		return refused(kDxlDataRangeError,
			       "FACTORY_RESET option " + std::to_string(option) + " (0xFF, 0x01 or 0x02)");
	if (how == DxlAddressing::broadcast && option == 0xFF) {
		DxlAnswer a;
		a.note = "FACTORY_RESET 0xFF to the broadcast ID is not executed";
		return a;
	}
	if (table_.get(kDxlTorqueEnable) == 1 || how == DxlAddressing::secondary)
		return refused(kDxlAccessError, "FACTORY_RESET refused: the EEPROM area is locked");
	table_.reset(option == 0xFF   ? DxlReset::factory_all
		     : option == 0x01 ? DxlReset::factory_but_id
				      : DxlReset::factory_but_id_baud);
	registered_.clear();
	drive_.power_on(table_);
	return {};
}

DxlAnswer DynamixelServo::reboot()
{
	table_.reset(DxlReset::reboot);
	registered_.clear();
	drive_.power_on(table_);
	return {};
}

DxlAnswer DynamixelServo::clear(const Dxl2Packet &p)
{
	if (p.params.size() != sizeof kClearMagic || !std::equal(p.params.begin(), p.params.end(), kClearMagic))
		return refused(kDxlDataRangeError, "CLEAR with params other than 01 44 58 4C 22");
	if (table_.get(kDxlMoving) == 1)
		return refused(kDxlResultFail, "CLEAR while moving");
	drive_.wrap_turns(table_);
	return {};
}

double DynamixelServo::step(double position_rad, double velocity_rad_s, double dt_s)
{
	return drive_.step(table_, position_rad, velocity_rad_s, dt_s);
}

} // namespace tcs
