// Each Protocol 2.0 instruction on XM430 servos (wires/serial/
// dynamixel_servo.h, dynamixel_chain.h), sent as the e-Manual's example
// packets: the status packets must be the e-Manual's, byte for byte, where
// its conditions can be made ours (its examples are of an XM430-W210,
// model 1030: our PING answers model 1020, firmware 46, its CRC computed
// by a separate implementation).
#include <cstdint>
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

const Bytes kOk = { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x55, 0x00, 0xA1, 0x0C };

DynamixelChain chain_of(std::vector<uint8_t> ids)
{
	DynamixelChain chain;
	for (uint8_t id : ids)
		assert_true(chain.add(id).ok());
	return chain;
}

// Servo i at rest at `counts`.
void place(DynamixelChain &chain, size_t i, double counts)
{
	chain.servo(i).step(angle_of(counts), 0, 0.001);
}

void ping_example(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	const std::vector<DxlReply> r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01, 0x19, 0x4E });
	assert_int_equal(r.size(), 1);
	assert_int_equal(r[0].id, 1);
	assert_int_equal(r[0].delay_ns, 500000); // Return Delay Time 250 * 2 us
	// Model Number 1020 (FC 03), firmware 46 (2E).
	assert_true(r[0].bytes ==
		    (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00, 0xFC, 0x03, 0x2E, 0x1D, 0x43 }));
}

void broadcast_ping_example(void **)
{
	DynamixelChain chain = chain_of({ 2, 1 });
	const std::vector<DxlReply> r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x03, 0x00, 0x01, 0x31, 0x42 });
	assert_int_equal(r.size(), 2);
	assert_true(r[0].bytes ==
		    (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00, 0xFC, 0x03, 0x2E, 0x1D, 0x43 }));
	assert_true(r[1].bytes ==
		    (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x02, 0x07, 0x00, 0x55, 0x00, 0xFC, 0x03, 0x2E, 0x17, 0x73 }));
}

void read_example(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	place(chain, 0, 166); // the e-Manual's Present Position
	const std::vector<DxlReply> r =
		send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x02, 0x84, 0x00, 0x04, 0x00, 0x1D, 0x15 });
	assert_int_equal(r.size(), 1);
	assert_true(r[0].bytes == (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x55, 0x00, 0xA6, 0x00, 0x00, 0x00,
					  0x8C, 0xC0 }));
}

void write_example(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	place(chain, 0, 2048);
	const std::vector<DxlReply> r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x09, 0x00, 0x03, 0x74, 0x00, 0x00,
						      0x02, 0x00, 0x00, 0xCA, 0x89 });
	assert_int_equal(r.size(), 1);
	assert_true(r[0].bytes == kOk);
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlGoalPosition), 512);
}

void reg_write_then_action_example(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	std::vector<DxlReply> r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x09, 0x00, 0x04, 0x68, 0x00, 0xC8, 0x00,
						0x00, 0x00, 0xAE, 0x8E });
	assert_true(r.size() == 1 && r[0].bytes == kOk);
	const tcs::DxlControlTable &t = chain.servo(0).table();
	assert_int_equal(t.get(tcs::kDxlRegisteredInstruction), 1);
	assert_int_equal(t.get(tcs::kDxlGoalVelocity), 0);
	r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x05, 0x02, 0xCE });
	assert_true(r.size() == 1 && r[0].bytes == kOk);
	assert_int_equal(t.get(tcs::kDxlGoalVelocity), 200);
	assert_int_equal(t.get(tcs::kDxlRegisteredInstruction), 0);
	// Again: nothing registered, Instruction Error (2).
	r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x05, 0x02, 0xCE });
	assert_true(r.size() == 1 &&
		    r[0].bytes == (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x55, 0x02, 0xAE, 0x8C }));
}

void factory_reset_example(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	const tcs::DxlControlTable &t = chain.servo(0).table();
	send(chain, write_of(1, tcs::kDxlReturnDelayTime, { 10 }));
	send(chain, write_of(1, tcs::kDxlOperatingMode, { 1 }));
	send(chain, write_of(1, tcs::kDxlId, { 3 }));
	assert_int_equal(t.get(tcs::kDxlReturnDelayTime), 10);
	assert_int_equal(chain.servo(0).id(), 3);
	// Option 0x01, all but the ID (the e-Manual's packet is to ID 1).
	std::vector<DxlReply> r = send(chain, tcs::dxl2_instruction(3, tcs::kDxlFactoryReset, Bytes{ 0x01 }));
	assert_int_equal(r.size(), 1);
	assert_int_equal(r[0].delay_ns, 20000); // the delay it had when the packet came
	assert_int_equal(t.get(tcs::kDxlReturnDelayTime), 250);
	assert_int_equal(t.get(tcs::kDxlOperatingMode), 3);
	assert_int_equal(chain.servo(0).id(), 3);
	// Option 0xFF: the ID too; the answer still from 3.
	r = send(chain, tcs::dxl2_instruction(3, tcs::kDxlFactoryReset, Bytes{ 0xFF }));
	assert_int_equal(r.size(), 1);
	assert_int_equal(status_of(r[0]).id, 3);
	assert_int_equal(chain.servo(0).id(), 1);
	// The e-Manual's packet, to ID 1 now.
	r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x06, 0x01, 0xA1, 0xE6 });
	assert_true(r.size() == 1 && r[0].bytes == kOk);
}

void reboot_example(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	const tcs::DxlControlTable &t = chain.servo(0).table();
	place(chain, 0, 2048);
	send(chain, write_of(1, tcs::kDxlReturnDelayTime, { 10 }));
	send(chain, write_of(1, tcs::kDxlTorqueEnable, { 1 }));
	place(chain, 0, 3000 + 4096); // a turn and more
	send(chain, write_of(1, tcs::kDxlLed, { 1 }));
	const std::vector<DxlReply> r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x08, 0x2F, 0x4E });
	assert_true(r.size() == 1 && r[0].bytes == kOk);
	// RAM back to its initial values, EEPROM kept.
	assert_int_equal(t.get(tcs::kDxlTorqueEnable), 0);
	assert_int_equal(t.get(tcs::kDxlLed), 0);
	assert_int_equal(t.get(tcs::kDxlReturnDelayTime), 10);
	// Restarted where it is: within a turn, its goal there.
	assert_int_equal(t.get(tcs::kDxlPresentPosition), 3000);
	assert_int_equal(t.get(tcs::kDxlGoalPosition), 3000);
	assert_int_equal(t.get(tcs::kDxlPresentInputVoltage), 120);
}

void clear_example(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	const tcs::DxlControlTable &t = chain.servo(0).table();
	place(chain, 0, 166);
	send(chain, write_of(1, tcs::kDxlOperatingMode, { 4 })); // extended position: all turns
	place(chain, 0, 166 + 2 * 4096);
	assert_int_equal(t.get(tcs::kDxlPresentPosition), 166 + 8192);
	const std::vector<DxlReply> r = send(
		chain, { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x10, 0x01, 0x44, 0x58, 0x4C, 0x22, 0xB1, 0xDC });
	assert_true(r.size() == 1 && r[0].bytes == kOk);
	assert_int_equal(t.get(tcs::kDxlPresentPosition), 166);
	// While moving (42 units > Moving Threshold 10): Result Fail (1).
	chain.servo(0).step(angle_of(166), 1.0, 0.001);
	const std::vector<DxlReply> moving =
		send(chain, tcs::dxl2_instruction(1, tcs::kDxlClear, Bytes{ 0x01, 0x44, 0x58, 0x4C, 0x22 }));
	assert_int_equal(status_of(moving[0]).params[0], tcs::kDxlResultFail);
}

void sync_read_example(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	place(chain, 0, 166);
	place(chain, 1, 2079);
	const std::vector<DxlReply> r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x09, 0x00, 0x82, 0x84, 0x00, 0x04,
						      0x00, 0x01, 0x02, 0xCE, 0xFA });
	assert_int_equal(r.size(), 2);
	assert_true(r[0].bytes == (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x55, 0x00, 0xA6, 0x00, 0x00, 0x00,
					  0x8C, 0xC0 }));
	assert_true(r[1].bytes == (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x02, 0x08, 0x00, 0x55, 0x00, 0x1F, 0x08, 0x00, 0x00,
					  0xBA, 0xBE }));
}

void sync_write_example(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	place(chain, 0, 2048);
	place(chain, 1, 2048);
	const std::vector<DxlReply> r =
		send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x11, 0x00, 0x83, 0x74, 0x00, 0x04, 0x00,
			      0x01, 0x96, 0x00, 0x00, 0x00, 0x02, 0xAA, 0x00, 0x00, 0x00, 0x82, 0x87 });
	assert_int_equal(r.size(), 0);
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlGoalPosition), 150);
	assert_int_equal(chain.servo(1).table().get(tcs::kDxlGoalPosition), 170);
}

void bulk_read_example(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	chain.servo(0).set_supply(11.9); // Present Input Voltage 119
	chain.servo(1).set_temperature(36);
	place(chain, 0, 2048);
	place(chain, 1, 2048);
	const std::vector<DxlReply> r = send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x0D, 0x00, 0x92, 0x01, 0x90,
						      0x00, 0x02, 0x00, 0x02, 0x92, 0x00, 0x01, 0x00, 0x1A, 0x05 });
	assert_int_equal(r.size(), 2);
	assert_true(r[0].bytes ==
		    (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x06, 0x00, 0x55, 0x00, 0x77, 0x00, 0xC3, 0x69 }));
	assert_true(r[1].bytes == (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x02, 0x05, 0x00, 0x55, 0x00, 0x24, 0x8B, 0xA9 }));
}

void bulk_write_example(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	send(chain, write_of(1, tcs::kDxlMaxVoltageLimit, le(150, 2)));
	send(chain, write_of(2, tcs::kDxlTemperatureLimit, { 70 }));
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlMaxVoltageLimit), 150);
	const std::vector<DxlReply> r =
		send(chain, { 0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x10, 0x00, 0x93, 0x01, 0x20, 0x00, 0x02,
			      0x00, 0xA0, 0x00, 0x02, 0x1F, 0x00, 0x01, 0x00, 0x50, 0xB7, 0x68 });
	assert_int_equal(r.size(), 0);
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlMaxVoltageLimit), 160);
	assert_int_equal(chain.servo(1).table().get(tcs::kDxlTemperatureLimit), 80);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(ping_example),
		cmocka_unit_test(broadcast_ping_example),
		cmocka_unit_test(read_example),
		cmocka_unit_test(write_example),
		cmocka_unit_test(reg_write_then_action_example),
		cmocka_unit_test(factory_reset_example),
		cmocka_unit_test(reboot_example),
		cmocka_unit_test(clear_example),
		cmocka_unit_test(sync_read_example),
		cmocka_unit_test(sync_write_example),
		cmocka_unit_test(bulk_read_example),
		cmocka_unit_test(bulk_write_example),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
