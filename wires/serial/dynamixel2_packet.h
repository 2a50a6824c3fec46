// ROBOTIS Dynamixel Protocol 2.0 packets (e-Manual, "Protocol 2.0"): the
// instruction and error codes, the CRC, byte stuffing, and building the
// bytes of an instruction or status packet.
//
//   FF FF FD 00 | id | length (LE) | instruction | params... | CRC (LE)
//
// length counts the instruction, the params and the CRC, after stuffing;
// the CRC covers everything from the header to the last param, stuffing
// included. A status packet is one whose instruction is 0x55 and whose
// first param is its error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tcs {

constexpr uint8_t kDxlBroadcastId = 0xFE;
constexpr uint8_t kDxlMaxId = 252; // 0xFD and 0xFF would read as a header

// Instructions.
constexpr uint8_t kDxlPing = 0x01;
constexpr uint8_t kDxlRead = 0x02;
constexpr uint8_t kDxlWrite = 0x03;
constexpr uint8_t kDxlRegWrite = 0x04;
constexpr uint8_t kDxlAction = 0x05;
constexpr uint8_t kDxlFactoryReset = 0x06;
constexpr uint8_t kDxlReboot = 0x08;
constexpr uint8_t kDxlClear = 0x10;
constexpr uint8_t kDxlStatus = 0x55;
constexpr uint8_t kDxlSyncRead = 0x82;
constexpr uint8_t kDxlSyncWrite = 0x83;
constexpr uint8_t kDxlBulkRead = 0x92;
constexpr uint8_t kDxlBulkWrite = 0x93;

// A status packet's error numbers (bit 7, the alert, is a hardware error).
constexpr uint8_t kDxlResultFail = 0x01;
constexpr uint8_t kDxlInstructionError = 0x02;
constexpr uint8_t kDxlCrcError = 0x03;
constexpr uint8_t kDxlDataRangeError = 0x04;
constexpr uint8_t kDxlDataLengthError = 0x05;
constexpr uint8_t kDxlDataLimitError = 0x06;
constexpr uint8_t kDxlAccessError = 0x07;

// The header and the length field; the bytes before the instruction.
constexpr size_t kDxl2HeadBytes = 7;

// A packet as received: params unstuffed.
struct Dxl2Packet {
	uint8_t id = 0;
	uint8_t instruction = 0;
	std::vector<uint8_t> params;

	bool operator==(const Dxl2Packet &) const = default;
};

// CRC-16 with polynomial 0x8005, MSB first, not reflected, from crc (0 for
// a packet's first bytes).
uint16_t dxl2_crc(const uint8_t *data, size_t n, uint16_t crc = 0);

// Byte stuffing: a 0xFD after every FF FF FD; and undone.
std::vector<uint8_t> dxl2_stuff(const uint8_t *data, size_t n);
std::vector<uint8_t> dxl2_unstuff(const uint8_t *data, size_t n);

// The bytes of an instruction packet; empty if its stuffed length would
// not fit the 16-bit length field.
std::vector<uint8_t> dxl2_instruction(uint8_t id, uint8_t instruction, const uint8_t *params, size_t n);
std::vector<uint8_t> dxl2_instruction(uint8_t id, uint8_t instruction, const std::vector<uint8_t> &params);

// The bytes of a status packet: instruction 0x55, the error, the params.
std::vector<uint8_t> dxl2_status(uint8_t id, uint8_t error, const uint8_t *params, size_t n);

} // namespace tcs
