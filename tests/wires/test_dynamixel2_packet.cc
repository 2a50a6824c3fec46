// Protocol 2.0 framing (wires/serial/dynamixel2_packet.h) and the parser
// (dynamixel2_parser.h): the e-Manual's example packets byte for byte, the
// CRC's catalogued check value, stuffing, and the parser's resync after
// garbage, a bad CRC and a bad length, whole or byte by byte. CRCs not in
// the e-Manual were computed by a separate bitwise implementation
// (Python), not by the code under test.
#include <cstdint>
#include <variant>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "dynamixel2_packet.h"
#include "dynamixel2_parser.h"

namespace {

using Bytes = std::vector<uint8_t>;
using tcs::Dxl2Fault;
using tcs::Dxl2Item;
using tcs::Dxl2Packet;
using tcs::Dxl2Parser;

// The e-Manual's examples (Protocol 2.0, "Instruction Details").
const Bytes kPing = { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01, 0x19, 0x4E };
const Bytes kPingStatus = { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00, 0x06, 0x04, 0x26, 0x65, 0x5D };
const Bytes kRead = { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x02, 0x84, 0x00, 0x04, 0x00, 0x1D, 0x15 };
const Bytes kReadStatus = { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x55, 0x00, 0xA6, 0x00, 0x00, 0x00, 0x8C, 0xC0 };
const Bytes kSyncWrite = { 0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x11, 0x00, 0x83, 0x74, 0x00, 0x04, 0x00,
			   0x01, 0x96, 0x00, 0x00, 0x00, 0x02, 0xAA, 0x00, 0x00, 0x00, 0x82, 0x87 };
const Bytes kBulkWrite = { 0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x10, 0x00, 0x93, 0x01, 0x20, 0x00, 0x02,
			   0x00, 0xA0, 0x00, 0x02, 0x1F, 0x00, 0x01, 0x00, 0x50, 0xB7, 0x68 };

std::vector<Dxl2Item> items_of(Dxl2Parser &p)
{
	std::vector<Dxl2Item> out;
	Dxl2Item it;
	while (p.next(it))
		out.push_back(it);
	return out;
}

std::vector<Dxl2Item> parse_whole(const Bytes &b)
{
	Dxl2Parser p;
	p.feed(b.data(), b.size());
	return items_of(p);
}

std::vector<Dxl2Item> parse_bytewise(const Bytes &b)
{
	Dxl2Parser p;
	for (uint8_t c : b)
		p.feed(&c, 1);
	return items_of(p);
}

Bytes cat(const Bytes &a, const Bytes &b)
{
	Bytes out = a;
	out.insert(out.end(), b.begin(), b.end());
	return out;
}

const Dxl2Packet &packet(const Dxl2Item &it)
{
	assert_true(std::holds_alternative<Dxl2Packet>(it));
	return std::get<Dxl2Packet>(it);
}

const Dxl2Fault &fault(const Dxl2Item &it)
{
	assert_true(std::holds_alternative<Dxl2Fault>(it));
	return std::get<Dxl2Fault>(it);
}

void crc_of_known_packets(void **)
{
	assert_int_equal(tcs::dxl2_crc(kPing.data(), 8), 0x4E19);
	assert_int_equal(tcs::dxl2_crc(kPingStatus.data(), 12), 0x5D65);
	assert_int_equal(tcs::dxl2_crc(kReadStatus.data(), 13), 0xC08C);
	// CRC-16/BUYPASS's catalogued check value.
	const uint8_t digits[] = { '1', '2', '3', '4', '5', '6', '7', '8', '9' };
	assert_int_equal(tcs::dxl2_crc(digits, 9), 0xFEE8);
	// Continued from a previous CRC: the same as at once.
	assert_int_equal(tcs::dxl2_crc(kPing.data() + 3, 5, tcs::dxl2_crc(kPing.data(), 3)), 0x4E19);
}

void builders_make_the_manual_packets(void **)
{
	assert_true(tcs::dxl2_instruction(1, tcs::kDxlPing, Bytes{}) == kPing);
	assert_true(tcs::dxl2_instruction(1, tcs::kDxlRead, Bytes{ 0x84, 0x00, 0x04, 0x00 }) == kRead);
	const Bytes status = { 0x06, 0x04, 0x26 };
	assert_true(tcs::dxl2_status(1, 0, status.data(), status.size()) == kPingStatus);
	const Bytes position = { 0xA6, 0x00, 0x00, 0x00 };
	assert_true(tcs::dxl2_status(1, 0, position.data(), position.size()) == kReadStatus);
	const Bytes sync(kSyncWrite.begin() + 8, kSyncWrite.end() - 2);
	assert_true(tcs::dxl2_instruction(0xFE, tcs::kDxlSyncWrite, sync) == kSyncWrite);
	const Bytes bulk(kBulkWrite.begin() + 8, kBulkWrite.end() - 2);
	assert_true(tcs::dxl2_instruction(0xFE, tcs::kDxlBulkWrite, bulk) == kBulkWrite);
	// The e-Manual's plain success status (WRITE, REG_WRITE, ACTION...).
	assert_true(tcs::dxl2_status(1, 0, nullptr, 0) ==
		    (Bytes{ 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x55, 0x00, 0xA1, 0x0C }));
}

void stuffing_by_hand(void **)
{
	const Bytes a = { 0xFF, 0xFF, 0xFD };
	assert_true(tcs::dxl2_stuff(a.data(), a.size()) == (Bytes{ 0xFF, 0xFF, 0xFD, 0xFD }));
	const Bytes b = { 0xFF, 0xFF, 0xFD, 0xFD };
	assert_true(tcs::dxl2_stuff(b.data(), b.size()) == (Bytes{ 0xFF, 0xFF, 0xFD, 0xFD, 0xFD }));
	const Bytes c = { 0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFD, 0x00 };
	const Bytes c_stuffed = { 0xFF, 0xFF, 0xFD, 0xFD, 0xFF, 0xFF, 0xFD, 0xFD, 0x00 };
	assert_true(tcs::dxl2_stuff(c.data(), c.size()) == c_stuffed);
	assert_true(tcs::dxl2_unstuff(c_stuffed.data(), c_stuffed.size()) == c);
	const Bytes d = { 0xFF, 0xFF, 0xFF, 0xFD, 0x01 }; // the last three make the pattern
	assert_true(tcs::dxl2_stuff(d.data(), d.size()) == (Bytes{ 0xFF, 0xFF, 0xFF, 0xFD, 0xFD, 0x01 }));
	const Bytes e = { 0xFF, 0xFD, 0xFF, 0xFD }; // no FF FF FD: nothing added
	assert_true(tcs::dxl2_stuff(e.data(), e.size()) == e);
}

void stuffing_round_trips(void **)
{
	// Bytes drawn from FF, FD and 00, where the patterns are frequent.
	uint32_t x = 12345;
	for (int round = 0; round < 2000; round++) {
		Bytes data(round % 40);
		for (uint8_t &b : data) {
			x = x * 1103515245u + 12345u;
			const uint8_t pick[3] = { 0xFF, 0xFD, 0x00 };
			b = pick[(x >> 16) % 3];
		}
		const Bytes s = tcs::dxl2_stuff(data.data(), data.size());
		assert_true(tcs::dxl2_unstuff(s.data(), s.size()) == data);
		// A packet carrying them parses back to them.
		const Bytes pkt = tcs::dxl2_instruction(7, tcs::kDxlWrite, data);
		const std::vector<Dxl2Item> got = parse_whole(pkt);
		assert_int_equal(got.size(), 1);
		assert_true(packet(got[0]).params == data);
	}
}

void a_stuffed_packet_by_hand(void **)
{
	// WRITE to id 1, address 0x41, data FF FF FD: a FD is stuffed in and
	// counted in the length (9); the CRC covers it.
	const Bytes bytes = { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x09, 0x00, 0x03,
			      0x41, 0x00, 0xFF, 0xFF, 0xFD, 0xFD, 0xF2, 0x9D };
	assert_true(tcs::dxl2_instruction(1, tcs::kDxlWrite, Bytes{ 0x41, 0x00, 0xFF, 0xFF, 0xFD }) == bytes);
	for (const auto &got : { parse_whole(bytes), parse_bytewise(bytes) }) {
		assert_int_equal(got.size(), 1);
		assert_true(packet(got[0]) == (Dxl2Packet{ 1, tcs::kDxlWrite, { 0x41, 0x00, 0xFF, 0xFF, 0xFD } }));
	}
}

void parser_takes_the_manual_packets(void **)
{
	const std::vector<Dxl2Item> got = parse_whole(cat(cat(kPing, kRead), kSyncWrite));
	assert_int_equal(got.size(), 3);
	assert_true(packet(got[0]) == (Dxl2Packet{ 1, tcs::kDxlPing, {} }));
	assert_true(packet(got[1]) == (Dxl2Packet{ 1, tcs::kDxlRead, { 0x84, 0x00, 0x04, 0x00 } }));
	assert_int_equal(packet(got[2]).id, 0xFE);
	assert_int_equal(packet(got[2]).params.size(), 14);
	// A status packet: instruction 0x55, the error its first param.
	const std::vector<Dxl2Item> status = parse_whole(kReadStatus);
	assert_true(packet(status[0]) == (Dxl2Packet{ 1, tcs::kDxlStatus, { 0x00, 0xA6, 0x00, 0x00, 0x00 } }));
}

void garbage_before_a_header_is_skipped(void **)
{
	// 00 12 and two FF that turn out not to start the header.
	const Bytes in = cat({ 0x00, 0x12, 0xFF, 0xFF }, kPing);
	const std::vector<Dxl2Item> whole = parse_whole(in);
	assert_int_equal(whole.size(), 2);
	assert_int_equal(fault(whole[0]).kind, Dxl2Fault::garbage);
	assert_int_equal(fault(whole[0]).bytes, 4);
	assert_true(packet(whole[1]) == (Dxl2Packet{ 1, tcs::kDxlPing, {} }));
	// Byte by byte: the same packet, the same bytes skipped in all.
	const std::vector<Dxl2Item> split = parse_bytewise(in);
	size_t skipped = 0;
	for (size_t i = 0; i + 1 < split.size(); i++)
		skipped += fault(split[i]).bytes;
	assert_int_equal(skipped, 4);
	assert_true(packet(split.back()) == packet(whole[1]));
	// FF FF FD FD is stuffing, not a header.
	const std::vector<Dxl2Item> stuffing = parse_whole(cat({ 0xFF, 0xFF, 0xFD, 0xFD }, kPing));
	assert_int_equal(fault(stuffing[0]).bytes, 4);
	assert_true(packet(stuffing[1]).instruction == tcs::kDxlPing);
}

void a_bad_crc_drops_the_packet(void **)
{
	Bytes bad = kPing;
	bad[9] = 0x4F;
	const std::vector<Dxl2Item> got = parse_whole(cat(bad, kPing));
	assert_int_equal(got.size(), 2);
	assert_true(fault(got[0]) == (Dxl2Fault{ Dxl2Fault::bad_crc, 1, tcs::kDxlPing, 3, 10 }));
	assert_true(packet(got[1]).instruction == tcs::kDxlPing);
}

void bad_lengths_drop_the_header(void **)
{
	const Bytes short_one = { 0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x02, 0x00 };
	std::vector<Dxl2Item> got = parse_whole(cat(short_one, kPing));
	assert_int_equal(got.size(), 2);
	assert_true(fault(got[0]) == (Dxl2Fault{ Dxl2Fault::bad_length, 5, 0, 2, 7 }));
	assert_true(packet(got[1]).instruction == tcs::kDxlPing);
	// 1025: one more than the receive buffer.
	const Bytes long_one = { 0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x01, 0x04 };
	got = parse_whole(cat(long_one, kPing));
	assert_int_equal(got.size(), 2);
	assert_true(fault(got[0]) == (Dxl2Fault{ Dxl2Fault::too_long, 5, 0, 1025, 7 }));
	assert_true(packet(got[1]).instruction == tcs::kDxlPing);
}

void the_longest_packet_is_taken(void **)
{
	// Length 1024: 1021 params.
	Bytes params(1021, 0x33);
	const Bytes pkt = tcs::dxl2_instruction(3, tcs::kDxlWrite, params);
	assert_int_equal(pkt.size(), 7 + 1024);
	const std::vector<Dxl2Item> got = parse_whole(pkt);
	assert_int_equal(got.size(), 1);
	assert_true(packet(got[0]).params == params);
}

void memory_stays_bounded(void **)
{
	// A header claiming 1024 bytes, then zeros: the parser never holds
	// more than one packet.
	Dxl2Parser p;
	const Bytes head = { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x00, 0x04 };
	p.feed(head.data(), head.size());
	const uint8_t zero = 0;
	for (int i = 0; i < 5000; i++) {
		p.feed(&zero, 1);
		assert_true(p.buffered() <= 7 + tcs::kDxl2MaxLength);
	}
	const std::vector<Dxl2Item> got = items_of(p);
	assert_true(fault(got[0]).kind == Dxl2Fault::bad_crc);
	assert_int_equal(fault(got[0]).bytes, 1031);
}

void a_partial_packet_dropped(void **)
{
	Dxl2Parser p;
	p.feed(kPing.data(), 6);
	assert_int_equal(p.buffered(), 6);
	p.drop_partial();
	assert_int_equal(p.buffered(), 0);
	p.feed(kPing.data(), kPing.size());
	const std::vector<Dxl2Item> got = items_of(p);
	assert_int_equal(got.size(), 2);
	assert_int_equal(fault(got[0]).bytes, 6);
	assert_true(packet(got[1]).instruction == tcs::kDxlPing);
}

void a_header_inside_a_packet_is_its_data(void **)
{
	// The length decides: FF FF FD 00 in the params (stuffed) ends nothing.
	const Bytes inner = tcs::dxl2_instruction(2, tcs::kDxlPing, Bytes{});
	const Bytes pkt = tcs::dxl2_instruction(1, tcs::kDxlWrite, cat({ 0x74, 0x00 }, inner));
	const std::vector<Dxl2Item> got = parse_bytewise(pkt);
	assert_int_equal(got.size(), 1);
	assert_true(packet(got[0]).params == cat({ 0x74, 0x00 }, inner));
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(crc_of_known_packets),
		cmocka_unit_test(builders_make_the_manual_packets),
		cmocka_unit_test(stuffing_by_hand),
		cmocka_unit_test(stuffing_round_trips),
		cmocka_unit_test(a_stuffed_packet_by_hand),
		cmocka_unit_test(parser_takes_the_manual_packets),
		cmocka_unit_test(garbage_before_a_header_is_skipped),
		cmocka_unit_test(a_bad_crc_drops_the_packet),
		cmocka_unit_test(bad_lengths_drop_the_header),
		cmocka_unit_test(the_longest_packet_is_taken),
		cmocka_unit_test(memory_stays_bounded),
		cmocka_unit_test(a_partial_packet_dropped),
		cmocka_unit_test(a_header_inside_a_packet_is_its_data),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
