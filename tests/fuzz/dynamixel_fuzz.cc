// The fuzz target for the Dynamixel Protocol 2.0 servos (wires/serial/):
// what a controller writes to the serial line, taken by Dxl2Parser whole
// and in pieces, every packet and fault handed to a chain of three XM430s
// stepped between packets. Promises: the pieces change no packet; the
// parser holds at most one packet; every reply is one well-formed status
// packet with a good CRC, from the servo it names; the torque stays within
// the motor's; and a packet built again from what was parsed parses back
// the same, split anywhere. The first byte picks the pieces' size, the
// second where the rebuilt packets are split; the rest is what was written.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "dynamixel2_parser.h"
#include "dynamixel_chain.h"
#include "dynamixel_motor.h"
#include "fuzz_target.h"

namespace {

using Bytes = std::vector<uint8_t>;
using tcs_fuzz::check;

// The largest status packet: a READ of the whole table, every byte stuffed
// at worst one in three.
constexpr size_t kMaxStatus = tcs::kDxl2HeadBytes + 2 + 2 * tcs::kDxlTableBytes + 2;
// The motor's largest torque: Kt at Current Limit's largest value.
const double kMaxTorque = tcs::kDxlKt * 1193 * tcs::kDxlCurrentUnit + 1e-9;

std::vector<tcs::Dxl2Item> parse(const uint8_t *data, size_t n, size_t piece)
{
	tcs::Dxl2Parser parser;
	std::vector<tcs::Dxl2Item> items;
	for (size_t at = 0; at < n; at += piece) {
		parser.feed(data + at, std::min(piece, n - at));
		check(parser.buffered() <= tcs::kDxl2HeadBytes + tcs::kDxl2MaxLength);
		tcs::Dxl2Item it;
		while (parser.next(it))
			items.push_back(std::move(it));
	}
	return items;
}

// What does not depend on the pieces: the packets and faults but for the
// count of garbage bytes, which may be reported in several parts.
std::vector<tcs::Dxl2Item> without_garbage(const std::vector<tcs::Dxl2Item> &items, size_t *garbage)
{
	std::vector<tcs::Dxl2Item> out;
	*garbage = 0;
	for (const tcs::Dxl2Item &it : items) {
		const tcs::Dxl2Fault *f = std::get_if<tcs::Dxl2Fault>(&it);
		if (f && f->kind == tcs::Dxl2Fault::garbage)
			*garbage += f->bytes;
		else
			out.push_back(it);
	}
	return out;
}

void check_reply(const tcs::DxlReply &r)
{
	check(r.bytes.size() <= kMaxStatus);
	check(r.delay_ns >= 0 && r.delay_ns <= 508000);
	const std::vector<tcs::Dxl2Item> back = parse(r.bytes.data(), r.bytes.size(), r.bytes.size() + 1);
	check(back.size() == 1);
	const tcs::Dxl2Packet *p = std::get_if<tcs::Dxl2Packet>(&back[0]);
	check(p != nullptr);
	check(p->id == r.id && p->id <= tcs::kDxlMaxId);
	check(p->instruction == tcs::kDxlStatus);
	check(!p->params.empty() && p->params[0] <= tcs::kDxlAccessError);
	// An error carries no data.
	check(p->params[0] == 0 || p->params.size() == 1);
}

// Built again and split at `cut`: the same packet.
void check_rebuilt(const tcs::Dxl2Packet &p, size_t cut)
{
	const Bytes bytes = tcs::dxl2_instruction(p.id, p.instruction, p.params);
	check(!bytes.empty());
	tcs::Dxl2Parser parser;
	cut %= bytes.size() + 1;
	parser.feed(bytes.data(), cut);
	parser.feed(bytes.data() + cut, bytes.size() - cut);
	tcs::Dxl2Item it;
	check(parser.next(it));
	check(std::holds_alternative<tcs::Dxl2Packet>(it) && std::get<tcs::Dxl2Packet>(it) == p);
	check(!parser.next(it) && parser.buffered() == 0);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 2)
		return 0;
	const size_t piece = data[0] < 128 ? size_t(data[0] % 16) + 1 : size_t(data[0]) * 8;
	const size_t cut_seed = data[1];
	const uint8_t *in = data + 2;
	const size_t n = size - 2;

	size_t garbage_whole, garbage_split;
	const std::vector<tcs::Dxl2Item> whole = without_garbage(parse(in, n, n + 1), &garbage_whole);
	const std::vector<tcs::Dxl2Item> split_items = parse(in, n, piece);
	const std::vector<tcs::Dxl2Item> split = without_garbage(split_items, &garbage_split);
	check(whole == split);
	check(garbage_whole == garbage_split);

	tcs::DynamixelChain chain;
	for (uint8_t id : { 1, 2, 3 })
		check(chain.add(id).ok());
	chain.servo(1).set_joint_inertia(0.002);
	size_t k = 0;
	for (const tcs::Dxl2Item &it : split_items) {
		// The joints somewhere, moving, between packets.
		for (size_t i = 0; i < chain.size(); i++) {
			const double theta = double(int(k % 17) - 8) * 0.9, omega = double(int(k % 5) - 2) * 2.1;
			const double tau = chain.servo(i).step(theta, omega, k % 7 == 6 ? 0.0 : 0.001);
			check(std::isfinite(tau) && std::fabs(tau) <= kMaxTorque);
		}
		std::vector<std::string> notes;
		const std::vector<tcs::DxlReply> replies =
			std::holds_alternative<tcs::Dxl2Packet>(it)
				? chain.handle(std::get<tcs::Dxl2Packet>(it), k % 3 ? 57600 : 0, &notes)
				: chain.handle(std::get<tcs::Dxl2Fault>(it), 0, &notes);
		for (const tcs::DxlReply &r : replies)
			check_reply(r);
		for (const std::string &note : notes)
			check(!note.empty());
		if (const tcs::Dxl2Packet *p = std::get_if<tcs::Dxl2Packet>(&it))
			check_rebuilt(*p, cut_seed * 31 + k);
		k++;
	}
	return 0;
}

const char *tcs_fuzz_name()
{
	return "dynamixel_fuzz";
}

namespace {

std::string text(const Bytes &b)
{
	return std::string(b.begin(), b.end());
}

Bytes write_of(uint8_t id, uint16_t addr, const Bytes &data)
{
	Bytes p = { uint8_t(addr), uint8_t(addr >> 8) };
	p.insert(p.end(), data.begin(), data.end());
	return tcs::dxl2_instruction(id, tcs::kDxlWrite, p);
}

} // namespace

std::vector<std::string> tcs_fuzz_seeds()
{
	using namespace tcs;
	const std::string head[] = { std::string("\x00\x07", 2), std::string("\x05\x31", 2),
				     std::string("\x83\x02", 2) };
	const std::vector<Bytes> streams = {
		// The e-Manual's examples: PING, READ, WRITE, REG_WRITE + ACTION,
		// FACTORY_RESET, REBOOT, CLEAR, SYNC/BULK READ and WRITE.
		dxl2_instruction(1, kDxlPing, Bytes{}),
		dxl2_instruction(0xFE, kDxlPing, Bytes{}),
		dxl2_instruction(1, kDxlRead, Bytes{ 0x84, 0x00, 0x04, 0x00 }),
		write_of(1, 116, { 0x00, 0x02, 0x00, 0x00 }),
		dxl2_instruction(1, kDxlRegWrite, Bytes{ 0x68, 0x00, 0xC8, 0x00, 0x00, 0x00 }),
		dxl2_instruction(1, kDxlAction, Bytes{}),
		dxl2_instruction(1, kDxlFactoryReset, Bytes{ 0x01 }),
		dxl2_instruction(1, kDxlReboot, Bytes{}),
		dxl2_instruction(1, kDxlClear, Bytes{ 0x01, 0x44, 0x58, 0x4C, 0x22 }),
		dxl2_instruction(0xFE, kDxlSyncRead, Bytes{ 0x84, 0x00, 0x04, 0x00, 0x01, 0x02, 0x03 }),
		dxl2_instruction(
			0xFE, kDxlSyncWrite,
			Bytes{ 0x74, 0x00, 0x04, 0x00, 0x01, 0x96, 0x00, 0x00, 0x00, 0x02, 0xAA, 0x00, 0x00, 0x00 }),
		dxl2_instruction(0xFE, kDxlBulkRead,
				 Bytes{ 0x01, 0x90, 0x00, 0x02, 0x00, 0x02, 0x92, 0x00, 0x01, 0x00 }),
		dxl2_instruction(0xFE, kDxlBulkWrite,
				 Bytes{ 0x01, 0x20, 0x00, 0x02, 0x00, 0xA0, 0x00, 0x02, 0x1F, 0x00, 0x01, 0x00, 0x50 }),
		// Torque on, goals in each mode, a profile, indirect addresses.
		[] {
			Bytes s;
			for (const Bytes &b :
			     { write_of(2, 11, { 5 }), write_of(2, 102, { 0xC8, 0x00 }),
			       write_of(2, 112, { 100, 0, 0, 0 }), write_of(2, 108, { 20, 0, 0, 0 }),
			       write_of(2, 64, { 1 }), write_of(2, 116, { 0, 8, 0, 0 }), write_of(3, 11, { 1 }),
			       write_of(3, 98, { 1 }), write_of(3, 64, { 1 }), write_of(3, 104, { 50, 0, 0, 0 }),
			       write_of(1, 168, { 132, 0, 133, 0, 134, 0, 135, 0 }),
			       dxl2_instruction(1, kDxlRead, Bytes{ 224, 0, 4, 0 }), write_of(1, 10, { 5 }),
			       write_of(1, 11, { 16 }), write_of(1, 64, { 1 }), write_of(1, 100, { 0x20, 0x03 }) })
				s.insert(s.end(), b.begin(), b.end());
			return s;
		}(),
		// Garbage, stuffing, a bad CRC, bad lengths.
		[] {
			Bytes s = { 0x00, 0xFF, 0xFF, 0xFF, 0xFD, 0xFD, 0x12 };
			Bytes w = write_of(1, 0x41, { 0xFF, 0xFF, 0xFD });
			s.insert(s.end(), w.begin(), w.end());
			w.back() ^= 1;
			s.insert(s.end(), w.begin(), w.end());
			const Bytes bad = { 0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x02, 0x00,
					    0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x01, 0x04 };
			s.insert(s.end(), bad.begin(), bad.end());
			return s;
		}(),
	};
	std::vector<std::string> seeds;
	for (size_t i = 0; i < streams.size(); i++)
		seeds.push_back(head[i % 3] + text(streams[i]));
	return seeds;
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { std::string("\xFF\xFF\xFD\x00", 4),
		 std::string("\xFF\xFF\xFD\xFD", 4),
		 std::string("\xFF\xFF\xFD", 3),
		 std::string("\x00\x04", 2),
		 std::string("\xFF\xFF", 2),
		 std::string("\xFE", 1),
		 std::string("\x55", 1),
		 std::string("\x82", 1),
		 std::string("\x92", 1),
		 std::string("\x93", 1),
		 std::string("\x74\x00", 2),
		 std::string("\x40\x00\x01", 3),
		 std::string("\xA8\x00", 2),
		 std::string("\x95\x02", 2) };
}

// A valid packet with fields worth trying, somewhere in the stream.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	if (s.size() < 2)
		return false;
	static const uint8_t kIds[] = { 1, 2, 3, 0xFE, 7, 0 };
	static const uint8_t kInstructions[] = { tcs::kDxlPing,      tcs::kDxlRead,     tcs::kDxlWrite,
						 tcs::kDxlRegWrite,  tcs::kDxlAction,   tcs::kDxlFactoryReset,
						 tcs::kDxlReboot,    tcs::kDxlClear,    tcs::kDxlSyncRead,
						 tcs::kDxlSyncWrite, tcs::kDxlBulkRead, tcs::kDxlBulkWrite };
	static const uint16_t kAddresses[] = {
		0,  7,   8,   9,   10,  11,  12,  13,  20,  38,  48,  63,  64,  65,  68,
		98, 100, 102, 104, 108, 112, 116, 120, 132, 168, 224, 578, 634, 660, 661
	};
	const uint8_t id = kIds[rng.below(sizeof kIds)];
	const uint8_t instruction = kInstructions[rng.below(sizeof kInstructions)];
	const uint16_t addr = kAddresses[rng.below(sizeof kAddresses / sizeof kAddresses[0])];
	Bytes params = { uint8_t(addr), uint8_t(addr >> 8) };
	const size_t n = rng.below(6);
	if (instruction == tcs::kDxlRead || instruction == tcs::kDxlSyncRead) {
		params.push_back(uint8_t(n));
		params.push_back(0);
	}
	for (size_t i = 0; i < n + (instruction == tcs::kDxlBulkRead ? 3 : 0); i++)
		params.push_back(uint8_t(rng.below(4) ? rng.below(5) : rng.next()));
	if (instruction == tcs::kDxlPing || instruction == tcs::kDxlAction || instruction == tcs::kDxlReboot)
		params.clear();
	const Bytes packet = tcs::dxl2_instruction(id, instruction, params);
	s.insert(2 + rng.below(s.size() - 1), std::string(packet.begin(), packet.end()));
	return true;
}
