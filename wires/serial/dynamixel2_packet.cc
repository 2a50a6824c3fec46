// Protocol 2.0's CRC, byte stuffing and packet building (see
// dynamixel2_packet.h).
#include "dynamixel2_packet.h"

namespace tcs {

namespace {

bool stuffing_due(const uint8_t *window)
{
	return window[0] == 0xFF && window[1] == 0xFF && window[2] == 0xFD;
}

std::vector<uint8_t> framed(uint8_t id, const std::vector<uint8_t> &body)
{
	const std::vector<uint8_t> stuffed = dxl2_stuff(body.data(), body.size());
	const size_t length = stuffed.size() + 2;
	if (length > 0xFFFF)
		return {};
	std::vector<uint8_t> out = { 0xFF, 0xFF, 0xFD, 0x00, id, uint8_t(length), uint8_t(length >> 8) };
	out.insert(out.end(), stuffed.begin(), stuffed.end());
	const uint16_t crc = dxl2_crc(out.data(), out.size());
	out.push_back(uint8_t(crc));
	out.push_back(uint8_t(crc >> 8));
	return out;
}

} // namespace

uint16_t dxl2_crc(const uint8_t *data, size_t n, uint16_t crc)
{
	for (size_t i = 0; i < n; i++) {
		crc ^= uint16_t(data[i] << 8);
		for (int bit = 0; bit < 8; bit++)
			crc = (crc & 0x8000) ? uint16_t(crc << 1) ^ 0x8005 : uint16_t(crc << 1);
	}
	return crc;
}

std::vector<uint8_t> dxl2_stuff(const uint8_t *data, size_t n)
{
	std::vector<uint8_t> out;
	out.reserve(n + n / 3);
	for (size_t i = 0; i < n; i++) {
		out.push_back(data[i]);
		if (i >= 2 && stuffing_due(data + i - 2))
			out.push_back(0xFD);
	}
	return out;
}

std::vector<uint8_t> dxl2_unstuff(const uint8_t *data, size_t n)
{
	// Judged on the bytes as received: an inserted FD never starts a
	// window of FF FF FD, so these windows are the sender's.
	std::vector<uint8_t> out;
	out.reserve(n);
	for (size_t i = 0; i < n; i++)
		if (!(i >= 3 && data[i] == 0xFD && stuffing_due(data + i - 3)))
			out.push_back(data[i]);
	return out;
}

std::vector<uint8_t> dxl2_instruction(uint8_t id, uint8_t instruction, const uint8_t *params, size_t n)
{
	std::vector<uint8_t> body;
	body.reserve(n + 1);
	body.push_back(instruction);
	body.insert(body.end(), params, params + n);
	return framed(id, body);
}

std::vector<uint8_t> dxl2_instruction(uint8_t id, uint8_t instruction, const std::vector<uint8_t> &params)
{
	return dxl2_instruction(id, instruction, params.data(), params.size());
}

std::vector<uint8_t> dxl2_status(uint8_t id, uint8_t error, const uint8_t *params, size_t n)
{
	std::vector<uint8_t> body;
	body.reserve(n + 2);
	body.push_back(kDxlStatus);
	body.push_back(error);
	body.insert(body.end(), params, params + n);
	return framed(id, body);
}

} // namespace tcs
