// What an XM430 refuses, and with which status error (wires/serial/
// dynamixel_control_table.h, dynamixel_servo.h): the EEPROM locked while
// torque is on, read-only items, gaps, items written in part, values out
// of range or past a limit; Indirect Addresses; Status Return Level. The
// status packets' CRCs were computed by a separate implementation.
#include <cstdint>
#include <string>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "dynamixel_checks.h"

namespace {

using namespace dxl_checks;
using tcs::DxlReply;
using tcs::DynamixelChain;

// Status packets from id 1 with no params: the error and its CRC.
Bytes status1(uint8_t error)
{
	static const uint8_t crc[8][2] = { { 0xA1, 0x0C }, { 0, 0 },       { 0xAE, 0x8C }, { 0xAB, 0x0C },
					   { 0xBA, 0x8C }, { 0xBF, 0x0C }, { 0xB5, 0x0C }, { 0xB0, 0x8C } };
	return { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x55, error, crc[error][0], crc[error][1] };
}

struct One {
	DynamixelChain chain;
	One()
	{
		assert_true(chain.add(1).ok());
		chain.servo(0).step(0, 0, 0.001);
	}
	const tcs::DxlControlTable &t() { return chain.servo(0).table(); }
	// The one status packet a packet gets.
	Bytes ask(const Bytes &packet)
	{
		const std::vector<DxlReply> r = send(chain, packet);
		assert_int_equal(r.size(), 1);
		return r[0].bytes;
	}
};

void eeprom_locked_while_torque_on(void **)
{
	One s;
	assert_true(s.ask(write_of(1, tcs::kDxlTorqueEnable, { 1 })) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlOperatingMode, { 1 })) == status1(tcs::kDxlAccessError));
	assert_int_equal(s.t().get(tcs::kDxlOperatingMode), 3);
	assert_true(s.ask(write_of(1, tcs::kDxlTorqueEnable, { 0 })) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlOperatingMode, { 1 })) == status1(0));
	assert_int_equal(s.t().get(tcs::kDxlOperatingMode), 1);
}

void read_only_and_gaps(void **)
{
	One s;
	assert_true(s.ask(write_of(1, tcs::kDxlPresentPosition, le(100, 4))) == status1(tcs::kDxlAccessError));
	assert_true(s.ask(write_of(1, tcs::kDxlModelNumber, le(1, 2))) == status1(tcs::kDxlAccessError));
	assert_true(s.ask(write_of(1, 66, { 0 })) == status1(tcs::kDxlAccessError));
	// Torque Enable, LED and the gap at 66: refused whole.
	assert_true(s.ask(write_of(1, tcs::kDxlTorqueEnable, { 1, 1, 0 })) == status1(tcs::kDxlAccessError));
	assert_int_equal(s.t().get(tcs::kDxlTorqueEnable), 0);
	assert_int_equal(s.t().get(tcs::kDxlLed), 0);
	// The two of them: both written.
	assert_true(s.ask(write_of(1, tcs::kDxlTorqueEnable, { 1, 1 })) == status1(0));
	assert_int_equal(s.t().get(tcs::kDxlLed), 1);
	// Past the table's last byte (661).
	assert_true(s.ask(write_of(1, 661, { 0, 0 })) == status1(tcs::kDxlAccessError));
}

void lengths(void **)
{
	One s;
	// 2 of Goal Position's 4 bytes.
	assert_true(s.ask(write_of(1, tcs::kDxlGoalPosition, { 0x00, 0x02 })) == status1(tcs::kDxlDataLengthError));
	// An address and no data.
	assert_true(s.ask(tcs::dxl2_instruction(1, tcs::kDxlWrite, Bytes{ 0x41, 0x00 })) ==
		    status1(tcs::kDxlDataLengthError));
	// READ with 3 params.
	assert_true(s.ask(tcs::dxl2_instruction(1, tcs::kDxlRead, Bytes{ 0x84, 0x00, 0x04 })) ==
		    status1(tcs::kDxlDataLengthError));
}

void ranges_and_limits(void **)
{
	One s;
	assert_true(s.ask(write_of(1, tcs::kDxlOperatingMode, { 2 })) == status1(tcs::kDxlDataRangeError));
	assert_true(s.ask(write_of(1, tcs::kDxlId, { 253 })) == status1(tcs::kDxlDataRangeError));
	assert_true(s.ask(write_of(1, tcs::kDxlDriveMode, { 0x02 })) == status1(tcs::kDxlDataRangeError));
	assert_true(s.ask(write_of(1, tcs::kDxlStatusReturnLevel, { 3 })) == status1(tcs::kDxlDataRangeError));
	// Position Control Mode: within Min/Max Position Limit (0-4095).
	assert_true(s.ask(write_of(1, tcs::kDxlGoalPosition, le(4096, 4))) == status1(tcs::kDxlDataLimitError));
	assert_true(s.ask(write_of(1, tcs::kDxlGoalPosition, le(-1, 4))) == status1(tcs::kDxlDataLimitError));
	assert_true(s.ask(write_of(1, tcs::kDxlMaxPositionLimit, le(3000, 4))) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlGoalPosition, le(3001, 4))) == status1(tcs::kDxlDataLimitError));
	// Extended Position Control Mode: +-1048575.
	assert_true(s.ask(write_of(1, tcs::kDxlOperatingMode, { 4 })) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlGoalPosition, le(-100000, 4))) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlGoalPosition, le(1048576, 4))) == status1(tcs::kDxlDataRangeError));
	// Goals within their limits: Velocity Limit 350.
	assert_true(s.ask(write_of(1, tcs::kDxlGoalVelocity, le(350, 4))) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlGoalVelocity, le(-351, 4))) == status1(tcs::kDxlDataLimitError));
	assert_true(s.ask(write_of(1, tcs::kDxlCurrentLimit, le(500, 2))) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlGoalCurrent, le(-600, 2))) == status1(tcs::kDxlDataLimitError));
	assert_true(s.ask(write_of(1, tcs::kDxlGoalCurrent, le(-500, 2))) == status1(0));
	assert_int_equal(s.t().get(tcs::kDxlGoalCurrent), -500);
}

void reads_span_gaps_not_the_end(void **)
{
	One s;
	// 64-71: Torque Enable, LED, 2 gap bytes, Status Return Level (2),
	// Registered Instruction, Hardware Error Status, a gap.
	const tcs::Dxl2Packet p = status_of(send(s.chain, read_of(1, 64, 8))[0]);
	assert_true(p.params == (Bytes{ 0, 0, 0, 0, 0, 2, 0, 0, 0 }));
	assert_true(s.ask(read_of(1, 660, 4)) == status1(tcs::kDxlAccessError));
}

void unknown_instruction(void **)
{
	One s;
	assert_true(s.ask(tcs::dxl2_instruction(1, 0x42, Bytes{})) == status1(tcs::kDxlInstructionError));
	// SYNC_READ to one ID, not the broadcast ID.
	assert_true(s.ask(tcs::dxl2_instruction(1, tcs::kDxlSyncRead, Bytes{ 0x84, 0x00, 0x04, 0x00, 0x01 })) ==
		    status1(tcs::kDxlInstructionError));
}

void indirect_addresses(void **)
{
	One s;
	s.chain.servo(0).step(angle_of(3000), 0, 0.001);
	// Indirect Address 1-4 at Present Position's bytes: Indirect Data 1-4
	// read it.
	Bytes at;
	for (int k = 0; k < 4; k++) {
		const Bytes a = le(tcs::kDxlPresentPosition + k, 2);
		at.insert(at.end(), a.begin(), a.end());
	}
	assert_true(s.ask(write_of(1, tcs::kDxlIndirectAddress1, at)) == status1(0));
	tcs::Dxl2Packet p = status_of(send(s.chain, read_of(1, tcs::kDxlIndirectData1, 4))[0]);
	assert_true(p.params == (Bytes{ 0, 0xB8, 0x0B, 0, 0 })); // 3000
	// Indirect Address 5 at LED: writing Indirect Data 5 lights it.
	assert_true(s.ask(write_of(1, tcs::kDxlIndirectAddress1 + 8, le(tcs::kDxlLed, 2))) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlIndirectData1 + 4, { 1 })) == status1(0));
	assert_int_equal(s.t().get(tcs::kDxlLed), 1);
	// Indirect Data 1-4 written through to read-only Present Position.
	assert_true(s.ask(write_of(1, tcs::kDxlIndirectData1, { 1, 2, 3, 4 })) == status1(tcs::kDxlAccessError));
	// An Indirect Address in the EEPROM area.
	assert_true(s.ask(write_of(1, tcs::kDxlIndirectAddress1 + 10, le(tcs::kDxlOperatingMode, 2))) ==
		    status1(tcs::kDxlDataRangeError));
	// Goal Position half mapped: written in part.
	Bytes half = le(tcs::kDxlGoalPosition, 2);
	const Bytes second = le(tcs::kDxlGoalPosition + 1, 2);
	half.insert(half.end(), second.begin(), second.end());
	assert_true(s.ask(write_of(1, tcs::kDxlIndirectAddress29, half)) == status1(0));
	assert_true(s.ask(write_of(1, tcs::kDxlIndirectData29, { 0, 8 })) == status1(tcs::kDxlDataLengthError));
	// Unmapped Indirect Data is plain storage.
	assert_true(s.ask(write_of(1, tcs::kDxlIndirectData29 + 5, { 0x5A })) == status1(0));
	assert_int_equal(status_of(send(s.chain, read_of(1, tcs::kDxlIndirectData29 + 5, 1))[0]).params[1], 0x5A);
}

void status_return_levels(void **)
{
	One s;
	// Answered at the level it found (2).
	assert_true(s.ask(write_of(1, tcs::kDxlStatusReturnLevel, { 1 })) == status1(0));
	assert_int_equal(send(s.chain, write_of(1, tcs::kDxlLed, { 1 })).size(), 0);
	assert_int_equal(s.t().get(tcs::kDxlLed), 1); // executed all the same
	assert_int_equal(send(s.chain, read_of(1, tcs::kDxlLed, 1)).size(), 1);
	assert_int_equal(send(s.chain, write_of(1, tcs::kDxlStatusReturnLevel, { 0 })).size(), 0);
	assert_int_equal(send(s.chain, read_of(1, tcs::kDxlLed, 1)).size(), 0);
	assert_int_equal(send(s.chain, tcs::dxl2_instruction(1, tcs::kDxlPing, Bytes{})).size(), 1);
	// An error is not answered either.
	assert_int_equal(send(s.chain, write_of(1, 66, { 0 })).size(), 0);
}

void notes_say_why(void **)
{
	One s;
	std::vector<std::string> notes;
	send(s.chain, write_of(1, tcs::kDxlPresentPosition, le(0, 4)), &notes);
	assert_int_equal(notes.size(), 1);
	assert_true(notes[0].find("id 1") != std::string::npos);
	assert_true(notes[0].find("read-only") != std::string::npos);
	notes.clear();
	send(s.chain, write_of(1, tcs::kDxlLed, { 1 }), &notes);
	assert_int_equal(notes.size(), 0);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(eeprom_locked_while_torque_on),
		cmocka_unit_test(read_only_and_gaps),
		cmocka_unit_test(lengths),
		cmocka_unit_test(ranges_and_limits),
		cmocka_unit_test(reads_span_gaps_not_the_end),
		cmocka_unit_test(unknown_instruction),
		cmocka_unit_test(indirect_addresses),
		cmocka_unit_test(status_return_levels),
		cmocka_unit_test(notes_say_why),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
