// Dxl2Parser: hunting for a header, receiving a packet, checking it (see
// dynamixel2_parser.h).
#include "dynamixel2_parser.h"

namespace tcs {

namespace {

constexpr uint8_t kHeader[4] = { 0xFF, 0xFF, 0xFD, 0x00 };

bool header_begun(const std::vector<uint8_t> &b)
{
	for (size_t i = 0; i < b.size(); i++)
		if (b[i] != kHeader[i])
			return false;
	return true;
}

std::string id_text(uint8_t id)
{
	return "id " + std::to_string(id);
}

} // namespace

std::string Dxl2Fault::note() const
{
	switch (kind) {
	case garbage:
		return "skipped " + std::to_string(bytes) + " bytes outside a packet";
	case bad_crc:
		return "dropped a packet to " + id_text(id) + " (instruction " + std::to_string(instruction) +
		       "): its CRC does not match";
	case bad_length:
		return "dropped a header to " + id_text(id) + ": length " + std::to_string(length) +
		       " leaves no room for an instruction and CRC";
	case too_long:
		return "dropped a header to " + id_text(id) + ": length " + std::to_string(length) +
		       " is more than the servo's receive buffer";
	}
	return "?";
}

Dxl2Parser::Dxl2Parser(size_t max_length) : max_length_(max_length < 3 ? 3 : max_length) {}

void Dxl2Parser::feed(const uint8_t *data, size_t n)
{
	for (size_t i = 0; i < n; i++)
		take(data[i]);
	report_skipped();
}

bool Dxl2Parser::next(Dxl2Item &out)
{
	if (out_.empty())
		return false;
	out = std::move(out_.front());
	out_.pop_front();
	return true;
}

void Dxl2Parser::drop_partial()
{
	skipped_ += buf_.size();
	buf_.clear();
	in_packet_ = false;
	report_skipped();
}

void Dxl2Parser::take(uint8_t b)
{
	if (!in_packet_) {
		hunt(b);
		return;
	}
	buf_.push_back(b);
	if (buf_.size() == kDxl2HeadBytes) {
		const size_t length = buf_[5] | size_t(buf_[6]) << 8;
		if (length < 3)
			refuse(Dxl2Fault::bad_length, kDxl2HeadBytes);
		else if (length > max_length_)
			refuse(Dxl2Fault::too_long, kDxl2HeadBytes);
	} else if (buf_.size() > kDxl2HeadBytes && buf_.size() == kDxl2HeadBytes + (buf_[5] | size_t(buf_[6]) << 8)) {
		finish();
	}
}

void Dxl2Parser::hunt(uint8_t b)
{
	// Of the bytes held, drop from the front until what is left can still
	// begin a header (FF FF FF: the last two can).
	buf_.push_back(b);
	while (!header_begun(buf_)) {
		buf_.erase(buf_.begin());
		skipped_++;
	}
	if (buf_.size() == sizeof kHeader) {
		report_skipped();
		in_packet_ = true;
	}
}

void Dxl2Parser::finish()
{
	const size_t n = buf_.size();
	const uint16_t got = uint16_t(buf_[n - 2] | buf_[n - 1] << 8);
	if (dxl2_crc(buf_.data(), n - 2) != got) {
		refuse(Dxl2Fault::bad_crc, n);
		return;
	}
	// Stuffing spans the instruction and the params: undone over both.
	std::vector<uint8_t> body = dxl2_unstuff(buf_.data() + kDxl2HeadBytes, n - kDxl2HeadBytes - 2);
	Dxl2Packet p;
	p.id = buf_[4];
	p.instruction = body[0];
	p.params.assign(body.begin() + 1, body.end());
	out_.push_back(std::move(p));
	buf_.clear();
	in_packet_ = false;
}

void Dxl2Parser::report_skipped()
{
	if (skipped_ == 0)
		return;
	Dxl2Fault f;
	f.bytes = skipped_;
	out_.push_back(f);
	skipped_ = 0;
}

void Dxl2Parser::refuse(Dxl2Fault::Kind kind, size_t bytes)
{
	Dxl2Fault f;
	f.kind = kind;
	f.id = buf_[4];
	f.length = uint16_t(buf_[5] | buf_[6] << 8);
	f.instruction = buf_.size() > kDxl2HeadBytes ? buf_[kDxl2HeadBytes] : 0;
	f.bytes = bytes;
	out_.push_back(f);
	buf_.clear();
	in_packet_ = false;
}

} // namespace tcs
