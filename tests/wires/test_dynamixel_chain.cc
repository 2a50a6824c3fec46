// A chain of servos on one line (wires/serial/dynamixel_chain.h): who
// answers (unknown IDs, the broadcast ID, a bad CRC, the Secondary ID, a
// servo at another baud), the order of SYNC/BULK_READ answers, and when
// the answers arrive on a SerialDirection, worked out by hand.
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

DynamixelChain chain_of(std::vector<uint8_t> ids)
{
	DynamixelChain chain;
	for (uint8_t id : ids)
		assert_true(chain.add(id).ok());
	for (size_t i = 0; i < chain.size(); i++)
		chain.servo(i).step(0, 0, 0.001);
	return chain;
}

std::vector<uint8_t> ids_of(const std::vector<DxlReply> &r)
{
	std::vector<uint8_t> ids;
	for (const DxlReply &x : r)
		ids.push_back(x.id);
	return ids;
}

Bytes with_bad_crc(Bytes b)
{
	b.back() ^= 0x01;
	return b;
}

void adding_servos(void **)
{
	DynamixelChain chain;
	assert_true(chain.add(1).ok());
	assert_false(chain.add(1).ok());
	assert_false(chain.add(253).ok());
	assert_true(chain.add(0).ok());
	assert_int_equal(chain.size(), 2);
}

void unknown_ids_and_the_broadcast_id(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	assert_int_equal(send(chain, tcs::dxl2_instruction(9, tcs::kDxlPing, Bytes{})).size(), 0);
	assert_int_equal(send(chain, read_of(9, tcs::kDxlLed, 1)).size(), 0);
	// WRITE to all: executed by each, answered by none.
	assert_int_equal(send(chain, write_of(0xFE, tcs::kDxlLed, { 1 })).size(), 0);
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlLed), 1);
	assert_int_equal(chain.servo(1).table().get(tcs::kDxlLed), 1);
	assert_int_equal(send(chain, read_of(0xFE, tcs::kDxlLed, 1)).size(), 0);
	// REBOOT to all: executed; FACTORY_RESET 0xFF to all: not.
	send(chain, write_of(0xFE, tcs::kDxlReturnDelayTime, { 7 }));
	assert_int_equal(send(chain, tcs::dxl2_instruction(0xFE, tcs::kDxlFactoryReset, Bytes{ 0xFF })).size(), 0);
	assert_int_equal(chain.servo(1).table().get(tcs::kDxlReturnDelayTime), 7);
	assert_int_equal(send(chain, tcs::dxl2_instruction(0xFE, tcs::kDxlReboot, Bytes{})).size(), 0);
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlLed), 0);
}

void a_bad_crc_gets_a_crc_error(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	std::vector<DxlReply> r = send(chain, with_bad_crc(write_of(1, tcs::kDxlLed, { 1 })));
	assert_int_equal(r.size(), 1);
	assert_true(r[0].bytes == (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x55, 0x03, 0xAB, 0x0C }));
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlLed), 0); // not executed
	assert_int_equal(send(chain, with_bad_crc(write_of(9, tcs::kDxlLed, { 1 }))).size(), 0);
	assert_int_equal(send(chain, with_bad_crc(write_of(0xFE, tcs::kDxlLed, { 1 }))).size(), 0);
	// At Status Return Level 1 a WRITE is not answered, a READ is.
	send(chain, write_of(1, tcs::kDxlStatusReturnLevel, { 1 }));
	assert_int_equal(send(chain, with_bad_crc(write_of(1, tcs::kDxlLed, { 1 }))).size(), 0);
	assert_int_equal(send(chain, with_bad_crc(read_of(1, tcs::kDxlLed, 1))).size(), 1);
}

void the_secondary_id(void **)
{
	DynamixelChain chain = chain_of({ 1, 2, 5 });
	send(chain, write_of(1, tcs::kDxlSecondaryId, { 5 }));
	send(chain, write_of(2, tcs::kDxlSecondaryId, { 5 }));
	// To 5: servo 5 answers; 1 and 2 execute silently.
	std::vector<DxlReply> r = send(chain, write_of(5, tcs::kDxlLed, { 1 }));
	assert_true(ids_of(r) == (std::vector<uint8_t>{ 5 }));
	for (size_t i = 0; i < 3; i++)
		assert_int_equal(chain.servo(i).table().get(tcs::kDxlLed), 1);
	// Not the EEPROM area through it.
	send(chain, write_of(5, tcs::kDxlReturnDelayTime, { 9 }));
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlReturnDelayTime), 250);
	assert_int_equal(chain.servo(2).table().get(tcs::kDxlReturnDelayTime), 9);
	// 253 and up turn it off.
	send(chain, write_of(1, tcs::kDxlSecondaryId, { 253 }));
	send(chain, write_of(5, tcs::kDxlLed, { 0 }));
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlLed), 1);
	assert_int_equal(chain.servo(1).table().get(tcs::kDxlLed), 0);
}

void a_new_id(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	std::vector<DxlReply> r = send(chain, write_of(1, tcs::kDxlId, { 7 }));
	assert_int_equal(status_of(r[0]).id, 1); // from the ID it was sent to
	assert_int_equal(send(chain, tcs::dxl2_instruction(1, tcs::kDxlPing, Bytes{})).size(), 0);
	r = send(chain, tcs::dxl2_instruction(7, tcs::kDxlPing, Bytes{}));
	assert_true(ids_of(r) == (std::vector<uint8_t>{ 7 }));
}

void sync_read_answers_in_the_packets_order(void **)
{
	DynamixelChain chain = chain_of({ 1, 2, 3 });
	send(chain, write_of(2, tcs::kDxlReturnDelayTime, { 10 }));
	// 3, 9 (no such servo), 1, 3 again, 2.
	const Bytes p = tcs::dxl2_instruction(0xFE, tcs::kDxlSyncRead, Bytes{ 0x84, 0x00, 0x04, 0x00, 3, 9, 1, 3, 2 });
	std::vector<DxlReply> r = send(chain, p);
	assert_true(ids_of(r) == (std::vector<uint8_t>{ 3, 1, 2 }));
	assert_int_equal(r[2].delay_ns, 20000);
	assert_int_equal(status_of(r[0]).params.size(), 5);
	// A servo at Status Return Level 0 is left out.
	send(chain, write_of(1, tcs::kDxlStatusReturnLevel, { 0 }));
	r = send(chain, p);
	assert_true(ids_of(r) == (std::vector<uint8_t>{ 3, 2 }));
	// Too few params: no one answers.
	std::vector<std::string> notes;
	assert_int_equal(
		send(chain, tcs::dxl2_instruction(0xFE, tcs::kDxlSyncRead, Bytes{ 0x84, 0x00, 0x04 }), &notes).size(),
		0);
	assert_int_equal(notes.size(), 1);
}

void bulk_read_answers_in_the_packets_order(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	// 2: LED (1 byte), 1: Present Position (4 bytes).
	const Bytes p = tcs::dxl2_instruction(0xFE, tcs::kDxlBulkRead, Bytes{ 2, 65, 0, 1, 0, 1, 132, 0, 4, 0 });
	std::vector<DxlReply> r = send(chain, p);
	assert_true(ids_of(r) == (std::vector<uint8_t>{ 2, 1 }));
	assert_int_equal(status_of(r[0]).params.size(), 2);
	assert_int_equal(status_of(r[1]).params.size(), 5);
	// A broken entry: ignored by all.
	assert_int_equal(send(chain, tcs::dxl2_instruction(0xFE, tcs::kDxlBulkRead, Bytes{ 2, 65, 0, 1, 0, 1 })).size(),
			 0);
}

void malformed_writes_to_many_are_ignored(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	// SYNC_WRITE of 1 byte at LED, entries of 2: 1 byte too many.
	send(chain, tcs::dxl2_instruction(0xFE, tcs::kDxlSyncWrite, Bytes{ 65, 0, 1, 0, 1, 1, 2, 1, 9 }));
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlLed), 0);
	send(chain, tcs::dxl2_instruction(0xFE, tcs::kDxlSyncWrite, Bytes{ 65, 0, 1, 0, 1, 1, 2, 1 }));
	assert_int_equal(chain.servo(1).table().get(tcs::kDxlLed), 1);
	// BULK_WRITE whose second entry claims more than is there.
	send(chain, tcs::dxl2_instruction(0xFE, tcs::kDxlBulkWrite, Bytes{ 1, 68, 0, 1, 0, 1, 2, 68, 0, 2, 0, 1 }));
	assert_int_equal(chain.servo(0).table().get(tcs::kDxlStatusReturnLevel), 2);
}

void another_baud_hears_nothing(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	const tcs::Dxl2Packet ping{ 1, tcs::kDxlPing, {} };
	assert_int_equal(chain.handle(ping, 57600).size(), 1); // Baud Rate 1: 57600
	assert_int_equal(chain.handle(ping, 1000000).size(), 0);
	chain.handle(tcs::Dxl2Packet{ 1, tcs::kDxlWrite, { 8, 0, 3 } }, 57600); // Baud Rate 3: 1 Mbit/s
	assert_int_equal(chain.servo(0).baud(), 1000000);
	assert_int_equal(chain.handle(ping, 57600).size(), 0);
	assert_int_equal(chain.handle(ping, 1000000).size(), 1);
	// Protocol Type 1: deaf to Protocol 2.0.
	chain.handle(tcs::Dxl2Packet{ 1, tcs::kDxlWrite, { 13, 0, 1 } });
	assert_int_equal(chain.handle(ping).size(), 0);
}

void a_read_round_trip_at_57600(void **)
{
	DynamixelChain chain = chain_of({ 1 });
	tcs::SerialDirection to_servo(57600, 10), to_controller(57600, 10);
	const Bytes read = read_of(1, tcs::kDxlPresentPosition, 4); // 14 bytes
	const int64_t sent = to_servo.send(read.size(), 0);
	assert_int_equal(sent, 2430555); // 140 bits: 2430555.6 ns
	const std::vector<DxlReply> r = send(chain, read);
	const std::vector<int64_t> at = tcs::dxl_send_replies(r, sent, to_controller);
	// 15 bytes back after the Return Delay Time (500 us): 2604166.7 ns.
	assert_int_equal(at.size(), 1);
	assert_int_equal(at[0], 2430555 + 500000 + 2604166);
	assert_int_equal(to_controller.arrival(0), 2430555 + 500000 + 173611);
}

void sync_read_answers_one_after_another(void **)
{
	DynamixelChain chain = chain_of({ 1, 2 });
	send(chain, write_of(0xFE, tcs::kDxlReturnDelayTime, { 0 })); // then 2: 4 us
	send(chain, write_of(2, tcs::kDxlReturnDelayTime, { 2 }));
	tcs::SerialDirection to_controller(1000000, 10);
	const Bytes p = tcs::dxl2_instruction(0xFE, tcs::kDxlSyncRead, Bytes{ 0x84, 0x00, 0x04, 0x00, 1, 2 });
	// 16 bytes at 1 Mbit/s end at 160 us; each answer of 15 bytes takes
	// 150 us, servo 2's after servo 1's and its 4 us.
	const std::vector<int64_t> at = tcs::dxl_send_replies(send(chain, p), 160000, to_controller);
	assert_int_equal(at.size(), 2);
	assert_int_equal(at[0], 160000 + 150000);
	assert_int_equal(at[1], 160000 + 150000 + 4000 + 150000);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(adding_servos),
		cmocka_unit_test(unknown_ids_and_the_broadcast_id),
		cmocka_unit_test(a_bad_crc_gets_a_crc_error),
		cmocka_unit_test(the_secondary_id),
		cmocka_unit_test(a_new_id),
		cmocka_unit_test(sync_read_answers_in_the_packets_order),
		cmocka_unit_test(bulk_read_answers_in_the_packets_order),
		cmocka_unit_test(malformed_writes_to_many_are_ignored),
		cmocka_unit_test(another_baud_hears_nothing),
		cmocka_unit_test(a_read_round_trip_at_57600),
		cmocka_unit_test(sync_read_answers_one_after_another),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
