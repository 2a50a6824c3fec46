// DynamixelChain: who hears a packet, who answers, in what order (see
// dynamixel_chain.h).
#include "dynamixel_chain.h"

#include <algorithm>

namespace tcs {

namespace {

void note(std::vector<std::string> *notes, const std::string &text)
{
	if (notes)
		notes->push_back("dynamixel: " + text);
}

void note_of(std::vector<std::string> *notes, uint8_t id, const std::string &text)
{
	if (!text.empty())
		note(notes, "id " + std::to_string(id) + ": " + text);
}

uint16_t le16(const uint8_t *p)
{
	return uint16_t(p[0] | p[1] << 8);
}

DxlReply reply_of(uint8_t id, int64_t delay_ns, const DxlAnswer &a)
{
	return DxlReply{ id, delay_ns, dxl2_status(id, a.error, a.params.data(), a.params.size()) };
}

// An ID's first listing in a SYNC/BULK packet.
bool first_listing(std::vector<bool> &seen, uint8_t id)
{
	if (seen[id])
		return false;
	seen[id] = true;
	return true;
}

} // namespace

Status DynamixelChain::add(uint8_t id)
{
	if (id > kDxlMaxId)
		return Error{ "dynamixel: id " + std::to_string(id) + " (0 to 252)" };
	for (const DynamixelServo &s : servos_)
		if (s.id() == id)
			return Error{ "dynamixel: two servos with id " + std::to_string(id) };
	servos_.emplace_back(id);
	return Ok{};
}

bool DynamixelChain::hears(const DynamixelServo &s, int64_t line_baud) const
{
	return s.listens() && (line_baud == 0 || s.baud() == line_baud);
}

std::vector<DxlReply> DynamixelChain::handle(const Dxl2Packet &p, int64_t line_baud, std::vector<std::string> *notes)
{
	std::vector<DxlReply> out;
	for (DynamixelServo &s : servos_)
		if (hears(s, line_baud))
			s.heard();
	if (p.id == kDxlBroadcastId) {
		switch (p.instruction) {
		case kDxlSyncRead:
			sync_read(p, line_baud, out, notes);
			return out;
		case kDxlSyncWrite:
			sync_write(p, line_baud, notes);
			return out;
		case kDxlBulkRead:
			bulk_read(p, line_baud, out, notes);
			return out;
		case kDxlBulkWrite:
			bulk_write(p, line_baud, notes);
			return out;
		default:
			break;
		}
	}
	for (DynamixelServo &s : servos_) {
		if (!hears(s, line_baud))
			continue;
		DxlAddressing how;
		if (p.id == kDxlBroadcastId)
			how = DxlAddressing::broadcast;
		else if (s.id() == p.id)
			how = DxlAddressing::id;
		else if (s.secondary_id() == p.id)
			how = DxlAddressing::secondary;
		else
			continue;
		// What the servo was when the packet came: a WRITE or a reset may
		// change its ID or delay, not the answer to this packet.
		const uint8_t id = s.id();
		const int64_t delay = s.return_delay_ns();
		const DxlAnswer a = s.execute(p, how);
		note_of(notes, id, a.note);
		if (a.sent)
			out.push_back(reply_of(id, delay, a));
	}
	if (p.id == kDxlBroadcastId)
		std::stable_sort(out.begin(), out.end(),
				 [](const DxlReply &a, const DxlReply &b) { return a.id < b.id; });
	return out;
}

std::vector<DxlReply> DynamixelChain::handle(const Dxl2Fault &f, int64_t line_baud, std::vector<std::string> *notes)
{
	std::vector<DxlReply> out;
	note(notes, f.note());
	if (f.kind != Dxl2Fault::bad_crc || f.id == kDxlBroadcastId)
		return out;
	for (DynamixelServo &s : servos_) {
		if (!hears(s, line_baud) || s.id() != f.id || !s.answers(f.instruction))
			continue;
		DxlAnswer a;
		a.error = kDxlCrcError;
		out.push_back(reply_of(s.id(), s.return_delay_ns(), a));
	}
	return out;
}

void DynamixelChain::read_of(uint8_t id, uint16_t addr, size_t n, int64_t baud, std::vector<DxlReply> &out,
			     std::vector<std::string> *notes)
{
	for (DynamixelServo &s : servos_) {
		if (!hears(s, baud) || s.id() != id || !s.answers(kDxlRead))
			continue;
		const DxlAnswer a = s.read(addr, n);
		note_of(notes, id, a.note);
		out.push_back(reply_of(id, s.return_delay_ns(), a));
	}
}

void DynamixelChain::write_to(uint8_t id, uint16_t addr, const uint8_t *data, size_t n, int64_t baud,
			      std::vector<std::string> *notes)
{
	for (DynamixelServo &s : servos_)
		if (hears(s, baud) && s.id() == id)
			note_of(notes, id, s.write(addr, data, n, DxlAddressing::broadcast).note);
}

void DynamixelChain::sync_read(const Dxl2Packet &p, int64_t baud, std::vector<DxlReply> &out,
			       std::vector<std::string> *notes)
{
	if (p.params.size() < 4) {
		note(notes, "SYNC_READ with " + std::to_string(p.params.size()) + " params, ignored");
		return;
	}
	std::vector<bool> seen(256);
	for (size_t i = 4; i < p.params.size(); i++)
		if (first_listing(seen, p.params[i]))
			read_of(p.params[i], le16(p.params.data()), le16(p.params.data() + 2), baud, out, notes);
}

void DynamixelChain::sync_write(const Dxl2Packet &p, int64_t baud, std::vector<std::string> *notes)
{
	const size_t n = p.params.size() >= 4 ? le16(p.params.data() + 2) : 0;
	if (n == 0 || (p.params.size() - 4) % (n + 1) != 0) {
		note(notes,
		     "SYNC_WRITE whose " + std::to_string(p.params.size()) + " params are no whole entries, ignored");
		return;
	}
	std::vector<bool> seen(256);
	for (size_t i = 4; i < p.params.size(); i += n + 1)
		if (first_listing(seen, p.params[i]))
			write_to(p.params[i], le16(p.params.data()), p.params.data() + i + 1, n, baud, notes);
}

void DynamixelChain::bulk_read(const Dxl2Packet &p, int64_t baud, std::vector<DxlReply> &out,
			       std::vector<std::string> *notes)
{
	if (p.params.empty() || p.params.size() % 5 != 0) {
		note(notes,
		     "BULK_READ whose " + std::to_string(p.params.size()) + " params are no whole entries, ignored");
		return;
	}
	std::vector<bool> seen(256);
	for (size_t i = 0; i < p.params.size(); i += 5)
		if (first_listing(seen, p.params[i]))
			read_of(p.params[i], le16(p.params.data() + i + 1), le16(p.params.data() + i + 3), baud, out,
				notes);
}

void DynamixelChain::bulk_write(const Dxl2Packet &p, int64_t baud, std::vector<std::string> *notes)
{
	// Every entry's length checked before any is written.
	std::vector<size_t> entries;
	size_t i = 0;
	while (i < p.params.size()) {
		if (p.params.size() - i < 5 || p.params.size() - i - 5 < le16(p.params.data() + i + 3)) {
			note(notes, "BULK_WRITE whose params are no whole entries, ignored");
			return;
		}
		entries.push_back(i);
		i += 5 + le16(p.params.data() + i + 3);
	}
	if (entries.empty())
		note(notes, "BULK_WRITE with no entries, ignored");
	std::vector<bool> seen(256);
	for (size_t at : entries) {
		const uint8_t *e = p.params.data() + at;
		if (first_listing(seen, e[0]))
			write_to(e[0], le16(e + 1), e + 5, le16(e + 3), baud, notes);
	}
}

std::vector<int64_t> dxl_send_replies(const std::vector<DxlReply> &replies, int64_t instruction_end_ns,
				      SerialDirection &to_controller)
{
	std::vector<int64_t> arrived;
	int64_t t = instruction_end_ns;
	for (const DxlReply &r : replies) {
		t = to_controller.send(r.bytes.size(), t + r.delay_ns);
		arrived.push_back(t);
	}
	return arrived;
}

} // namespace tcs
