// DynamixelServo: one ROBOTIS XM430-W350 (T or R) speaking Protocol 2.0:
// its control table (dynamixel_control_table.h), the instructions it
// executes and what it answers, and its motion (dynamixel_drive.h). Which
// servos hear a packet, and in what order they answer, is the chain's
// (dynamixel_chain.h).
//
// Instructions, as the e-Manual's "Protocol 2.0" describes them, and what
// we decided where it says nothing:
//   PING: Model Number and Firmware Version, at any Status Return Level.
//   READ: params address, length (4 bytes, else Data Length Error).
//   WRITE: params address, data (3 bytes or more, else Data Length Error);
//     checked as DxlControlTable::stage() says.
//   REG_WRITE: a WRITE checked now, applied at ACTION (Registered
//     Instruction = 1); ACTION with none registered: Instruction Error.
//   FACTORY_RESET: option 0xFF (all), 0x01 (all but ID), 0x02 (all but ID
//     and Baud Rate); another option: Data Range Error. To the broadcast
//     ID with 0xFF it is not executed (firmware 42 on). While torque is on:
//     Access Error, as for any EEPROM write. The servo restarts after it.
//   REBOOT: the RAM area back to its initial values, torque off.
//   CLEAR: option 0x01 and 44 58 4C 22 resets Present Position to within
//     a turn; Result Fail while moving; other params: Data Range Error.
//   SYNC_*/BULK_*: only to the broadcast ID; to one ID: Instruction Error.
//   Any other instruction: Instruction Error. A status packet (0x55) from
//     another device is ignored.
// A status packet goes out as Status Return Level(68) allows (0: PING only,
// 1: PING and READ, 2: all), never to the Secondary ID, and to the
// broadcast ID only for PING. It carries the ID the packet was sent to
// (a WRITE to ID(7) answers from the old one).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dynamixel2_packet.h"
#include "dynamixel_control_table.h"
#include "dynamixel_drive.h"

namespace tcs {

enum class DxlAddressing {
	id,        // the packet's ID is the servo's
	broadcast, // 0xFE, or the servo's ID in a SYNC/BULK instruction
	secondary, // the packet's ID is the servo's Secondary ID(12)
};

// What a servo makes of an instruction.
struct DxlAnswer {
	bool sent = false; // a status packet goes out
	uint8_t error = 0;
	std::vector<uint8_t> params;
	std::string note; // why it was refused or ignored, for the log
};

class DynamixelServo {
public:
	// At factory settings but for its ID (1 to 252).
	explicit DynamixelServo(uint8_t id = 1);

	uint8_t id() const { return uint8_t(table_.get(kDxlId)); }
	// Secondary ID(12), or -1 while off (253 and up).
	int secondary_id() const;
	// Return Delay Time(9): 2 us a unit.
	int64_t return_delay_ns() const { return table_.get(kDxlReturnDelayTime) * 2000; }
	// Baud Rate(8) in bit/s.
	int64_t baud() const;
	// Protocol Type(13) is 2.0: set to 1.0, the servo no longer hears
	// Protocol 2.0 packets (as the real one, until reset through 1.0).
	bool listens() const { return table_.get(kDxlProtocolType) == 2; }
	// Whether a packet to its ID with this instruction is answered.
	bool answers(uint8_t instruction) const;

	DxlAnswer execute(const Dxl2Packet &p, DxlAddressing how);
	// READ and WRITE as SYNC and BULK instructions ask them.
	DxlAnswer read(uint16_t addr, size_t n) const;
	DxlAnswer write(uint16_t addr, const uint8_t *data, size_t n, DxlAddressing how);
	// An instruction packet heard on the bus (the Bus Watchdog's count).
	void heard() { drive_.heard(); }

	// One simulation step: the joint's angle (rad) and velocity (rad/s)
	// read, the servo's loop run for dt_s; returns the torque it puts on
	// the joint (N*m), 0 while torque is off.
	double step(double position_rad, double velocity_rad_s, double dt_s);

	// The joint's inertia about its axis (kg*m^2), if known: the motor's
	// back-EMF damping (0.85 N*m*s/rad) is then applied exactly over a
	// step, not as an explicit damper, which a light joint at a long step
	// would make oscillate. 0 (the default): explicit.
	void set_joint_inertia(double kg_m2) { drive_.set_joint_inertia(kg_m2); }
	// The supply (12 V: Present Input Voltage 120) and Present Temperature.
	void set_supply(double volts) { drive_.set_supply(volts); }
	void set_temperature(double celsius) { drive_.set_temperature(celsius); }

	const DxlControlTable &table() const { return table_; }

private:
	DxlAnswer ping() const;
	DxlAnswer reg_write(const Dxl2Packet &p, DxlAddressing how);
	DxlAnswer action();
	DxlAnswer factory_reset(const Dxl2Packet &p, DxlAddressing how);
	DxlAnswer reboot();
	DxlAnswer clear(const Dxl2Packet &p);
	// What a committed WRITE sets going (torque on, a new mode, a goal).
	void written(const DxlControlTable::Staged &s, int64_t torque_before, int64_t mode_before);

	DxlControlTable table_;
	DxlDrive drive_;
	std::vector<uint8_t> registered_; // REG_WRITE's address and data
};

} // namespace tcs
