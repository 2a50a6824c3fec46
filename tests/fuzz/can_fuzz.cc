// The fuzz target for the CAN wire (wires/can/): what controllers write to
// a CAN_RAW socket, taken by frame_from_linux() as sendmsg takes it, then
// given to what meets a frame on the bus: its bit count (can_frame_bits),
// an MIT motor (MitMotor::receive) and a frame of signals (can_unpack);
// and sequences of submits and advances to a CanBus, whose promises are
// checked against a record of what was submitted.
//
// The first byte picks what the rest is. Even: frames. Byte 1: a layout's
// field count (bits 0-2), FD (bit 3), FD sockets (bit 4); two bytes a
// field; then frames, each a size byte (< 128: CAN_MTU, < 240: CANFD_MTU,
// else (s - 240) · 5 bytes) and the bytes. Odd: a bus; the rest operations
// (can_bus_ops below).
#include <linux/can.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "can_bus_promises.h"
#include "can_frame.h"
#include "can_frame_time.h"
#include "can_signals.h"
#include "fuzz_target.h"
#include "mit_motor.h"

namespace {

using tcs::CanFrame;
using tcs_fuzz::check;

const double kScales[] = { 1, 0.5, 0.01, 2, -1, 0.125, 10, -0.25 };
const double kOffsets[] = { 0, 100, -40, 0.5 };

bool is_fd_len(size_t len)
{
	return tcs::can_fd_len(len) == len;
}

// What frame_from_linux promises of a frame it accepts.
void check_frame(const CanFrame &f, size_t n)
{
	check(f.fd == (n == CANFD_MTU));
	check(f.id <= (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK));
	check(f.fd ? is_fd_len(f.len) && f.len <= 64 : f.len <= 8);
	check(!(f.fd && f.rtr) && (f.fd || (!f.brs && !f.esi)));
	for (size_t i = f.rtr ? 0 : f.len; i < sizeof f.data; i++)
		check(f.data[i] == 0);
	// Written out and read back: the same frame.
	uint8_t out[CANFD_MTU];
	tcs::frame_to_linux(f, out, tcs::linux_frame_size(f));
	tcs::Result<CanFrame> back = tcs::frame_from_linux(out, tcs::linux_frame_size(f), true);
	check(back.ok());
	check(back->id == f.id && back->extended == f.extended && back->rtr == f.rtr && back->fd == f.fd &&
	      back->brs == f.brs && back->esi == f.esi && back->len == f.len &&
	      memcmp(back->data, f.data, sizeof f.data) == 0);
}

// The bit count lies between no stuffing and the most the stuffed bits allow.
void check_bits(const CanFrame &f)
{
	const tcs::CanFrameBits b = tcs::can_frame_bit_split(f);
	check(b.nominal > 0 && b.data >= 0 && (b.data == 0 || (f.fd && f.brs)));
	int stuffed, base;
	if (f.fd) {
		const int len = tcs::can_fd_len(f.len);
		stuffed = (f.extended ? 41 : 22) + 8 * len;
		base = stuffed + (len <= 16 ? 27 : 32) + 13;
	} else {
		const int data = f.rtr ? 0 : 8 * (f.len > 8 ? 8 : f.len);
		stuffed = (f.extended ? 54 : 34) + data;
		base = stuffed + 13;
	}
	const int bits = tcs::can_frame_bits(f);
	check(bits == b.nominal + b.data);
	check(bits >= base && bits <= base + (stuffed - 1) / 4);
	check(tcs::can_frame_ns(f, 1000000, 0) == 1000 * int64_t(bits));
}

// Joint states a frame's bytes pick, the strange ones among them.
double state(uint8_t b)
{
	switch (b & 15) {
	case 0:
		return NAN;
	case 1:
		return INFINITY;
	case 2:
		return -1e300;
	default:
		return (int8_t(b) / 8.0);
	}
}

void check_motor(tcs::MitMotor &m, const CanFrame &f)
{
	const double p = state(f.data[1]), v = state(f.data[2]), t = state(f.data[3]);
	std::string note;
	const std::optional<CanFrame> reply = m.receive(f, p, v, t, &note);
	if (reply) {
		check(reply->len == 6 && !reply->rtr && !reply->fd && !reply->extended && reply->id == 0);
		check(reply->data[0] == m.id() && note.empty());
		check(f.id == m.id() && !f.extended && !f.fd && !f.rtr && f.len == 8);
	} else {
		// Ignored: said why when it was its own id.
		check(note.empty() == (f.id != m.id()));
	}
	const double tau = m.torque(p, v);
	check(std::isfinite(tau) && std::fabs(tau) <= 5);
	check(m.enabled() || tau == 0);
}

void check_signals(const tcs::CanLayout &l, const CanFrame &f)
{
	std::vector<double> values, again;
	std::string why;
	const bool ok = tcs::can_unpack(l, f, values, &why);
	check(ok == (f.len >= l.end));
	if (!ok) {
		check(!why.empty() && values.empty());
		return;
	}
	check(values.size() == l.fields.size());
	// Packed again and read back: integers exactly, floats where the
	// arithmetic is exact (no offset, a power-of-two scale).
	CanFrame g;
	tcs::can_pack(l, values.data(), g);
	check(g.len == l.len && g.fd == l.fd);
	check(tcs::can_unpack(l, g, again, nullptr));
	for (size_t i = 0; i < values.size(); i++) {
		const tcs::CanField &field = l.fields[i];
		if (field.type != tcs::CanType::float32)
			check(again[i] == values[i]);
		else if (field.offset == 0 && std::fabs(field.scale) != 0.01 && std::fabs(field.scale) != 10)
			check(again[i] == values[i] || (std::isnan(again[i]) && std::isnan(values[i])));
	}
}

// Byte 1 and the fields' bytes: a layout, when it is a valid one.
std::optional<tcs::CanLayout> layout_from(const uint8_t *&data, size_t &size)
{
	if (size < 1)
		return std::nullopt;
	const int count = data[0] & 7;
	const bool fd = data[0] & 8;
	data++, size--;
	std::vector<tcs::CanField> fields;
	for (int i = 0; i < count && size >= 2; i++, data += 2, size -= 2) {
		tcs::CanField f;
		f.name = "f" + std::to_string(i);
		f.type = tcs::CanType((data[0] & 7) % 7);
		f.order = data[0] & 8 ? tcs::CanByteOrder::big : tcs::CanByteOrder::little;
		f.scale = kScales[data[0] >> 4 & 7];
		f.offset = kOffsets[data[1] & 3];
		f.start = data[1] & 4 ? int(data[1] >> 3) : -1;
		fields.push_back(f);
	}
	tcs::Result<tcs::CanLayout> l = tcs::can_layout(fields, fd);
	if (!l.ok()) {
		check(l.error().message.find("field '") == 0);
		return std::nullopt;
	}
	check(l->end <= (fd ? 64 : 8) && l->fields.size() == fields.size());
	return *l;
}

void frames(const uint8_t *data, size_t size)
{
	const bool fd_sockets = size > 0 && data[0] & 16;
	const std::optional<tcs::CanLayout> layout = layout_from(data, size);
	tcs::MitMotor motor(1);
	while (size > 0) {
		const uint8_t s = data[0];
		data++, size--;
		size_t n = s < 128 ? CAN_MTU : s < 240 ? CANFD_MTU : size_t(s - 240) * 5;
		if (n > size)
			n = size;
		tcs::Result<CanFrame> f = tcs::frame_from_linux(data, n, fd_sockets);
		data += n, size -= n;
		if (!f.ok()) {
			check(!f.error().message.empty());
			continue;
		}
		check(n == CAN_MTU || (fd_sockets && n == CANFD_MTU));
		check_frame(*f, n);
		check_bits(*f);
		check_motor(motor, *f);
		// The same bytes to the motor's own id.
		CanFrame mine = *f;
		mine.id = 1;
		check_motor(motor, mine);
		if (layout)
			check_signals(*layout, *f);
	}
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size == 0)
		return 0;
	if (data[0] & 1)
		can_bus_ops(data + 1, size - 1);
	else
		frames(data + 1, size - 1);
	return 0;
}

const char *tcs_fuzz_name()
{
	return "can_fuzz";
}

namespace {

std::string classic_bytes(uint32_t can_id, std::vector<uint8_t> data)
{
	struct can_frame f;
	memset(&f, 0, sizeof f);
	f.can_id = can_id;
	f.len = uint8_t(data.size());
	memcpy(f.data, data.data(), data.size() > 8 ? 8 : data.size());
	return std::string(1, '\0') + std::string(reinterpret_cast<const char *>(&f), sizeof f);
}

std::string fd_bytes(uint32_t can_id, uint8_t len, uint8_t flags, uint8_t fill)
{
	struct canfd_frame f;
	memset(&f, 0, sizeof f);
	f.can_id = can_id;
	f.len = len;
	f.flags = flags;
	memset(f.data, fill, sizeof f.data);
	return std::string(1, '\x80') + std::string(reinterpret_cast<const char *>(&f), sizeof f);
}

} // namespace

std::vector<std::string> tcs_fuzz_seeds()
{
	const std::vector<uint8_t> enter = { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFC };
	const std::vector<uint8_t> zero = { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFE };
	const std::vector<uint8_t> command = { 0x8A, 0x3C, 0x85, 0x10, 0x51, 0x33, 0x36, 0x66 };
	// Byte 1: 3 fields (int16 LE ·0.5, uint8 +100, int32 BE +100 at byte 4), FD sockets.
	const std::string head = std::string("\x00\x13\x11\x00\x03\x01\x0a\x25", 8);
	return {
		head + classic_bytes(1, enter) + classic_bytes(1, command) + classic_bytes(1, zero) +
			classic_bytes(1, { 1, 2, 3 }),
		head + classic_bytes(CAN_EFF_FLAG | 1, command) + classic_bytes(CAN_RTR_FLAG | 1, { 0, 0 }) +
			classic_bytes(CAN_ERR_FLAG | 0x7FF, { 0xFF }) +
			classic_bytes(0x123, std::vector<uint8_t>(9, 1)),
		// 2 float32 fields, FD frames and sockets.
		std::string("\x00\x1a\x06\x00\x86\x00", 6) + fd_bytes(0x55, 64, CANFD_BRS, 0x55) +
			fd_bytes(CAN_EFF_FLAG | 0x1FFFFFFF, 9, CANFD_ESI, 0) + fd_bytes(1, 65, 0, 0xFF),
		std::string("\x00\x00", 2) + "\xf3" + std::string(15, '\0') + "\xf0",
		can_bus_seed(),
	};
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { std::string("\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFC", 8),
		 std::string("\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFD", 8),
		 std::string("\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFE", 8),
		 std::string("\x01\x00\x00\x00", 4),
		 std::string("\x01\x00\x00\x80", 4),
		 std::string("\x00\x00\x00\x40", 4),
		 std::string("\x00\x00\x00\x20", 4),
		 std::string("\x08", 1),
		 std::string("\x40", 1),
		 std::string("\x09", 1) };
}

// A frame's size byte, its id or its len written over.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	if (s.size() < 8)
		return false;
	const size_t at = 1 + rng.below(s.size() - 1);
	switch (rng.below(3)) {
	case 0:
		s[at] = char(rng.below(2) ? 0 : 0x80);
		break;
	case 1:
		tcs_fuzz::put_le(s, at, rng.below(2) ? rng.below(0x800) : (rng.next() | CAN_EFF_FLAG), 4);
		break;
	default:
		s[at] = char(rng.below(2) ? 8 : rng.below(66));
	}
	return true;
}
