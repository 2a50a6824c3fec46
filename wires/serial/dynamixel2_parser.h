// Dxl2Parser: Protocol 2.0 packets taken from a byte stream as a servo's
// receiver takes them, whatever the pieces the bytes come in; and what it
// skipped or refused on the way, for the coordinator to log.
//
// As the e-Manual's "Processing Order of Reception" has it: hunt for the
// header FF FF FD 00 (skipping what precedes it), read the length, take
// that many bytes, check the CRC over the bytes as received, then undo the
// stuffing. A packet whose length is below 3 or above max_length is
// dropped with its 7 header bytes, and the hunt goes on after them; one
// whose CRC is wrong is dropped whole. Memory: one packet being received
// (at most 7 + max_length bytes) and the items not yet taken.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <variant>
#include <vector>

#include "dynamixel2_packet.h"

namespace tcs {

// The longest length field taken. The e-Manual gives no figure for the
// X-series' receive buffer; ROBOTIS's DynamixelSDK keeps 1 KiB for a
// packet on the host side, which any packet its tools make fits, and so
// does ours (a SYNC_WRITE of 4 bytes to 200 servos: 1007).
constexpr size_t kDxl2MaxLength = 1024;

// What a receiver drops.
struct Dxl2Fault {
	enum Kind {
		garbage,    // bytes skipped while hunting for a header
		bad_crc,    // a whole packet whose CRC did not match
		bad_length, // a length below 3: no room for the instruction and CRC
		too_long,   // a length above the receive buffer
	};
	Kind kind = garbage;
	uint8_t id = 0;          // not for garbage
	uint8_t instruction = 0; // bad_crc: the instruction byte as received
	uint16_t length = 0;     // the length field (not for garbage)
	size_t bytes = 0;        // how many bytes were dropped

	bool operator==(const Dxl2Fault &) const = default;
	// One line for a log: "skipped 5 bytes before a header", ...
	std::string note() const;
};

using Dxl2Item = std::variant<Dxl2Packet, Dxl2Fault>;

class Dxl2Parser {
public:
	explicit Dxl2Parser(size_t max_length = kDxl2MaxLength);

	// Takes bytes; complete packets and faults wait for next(). Bytes
	// skipped are reported once a header is found, and at the end of each
	// feed.
	void feed(const uint8_t *data, size_t n);

	// The oldest item not yet taken; false when there is none.
	bool next(Dxl2Item &out);

	// Drops a packet half received (and a header begun), as garbage: for
	// a line that went quiet, or was flushed, before its end came.
	void drop_partial();

	// Bytes of a packet (or header) received so far.
	size_t buffered() const { return buf_.size(); }

private:
	void take(uint8_t b);
	void hunt(uint8_t b);
	void finish();
	void report_skipped();
	void refuse(Dxl2Fault::Kind kind, size_t bytes);

	size_t max_length_;
	std::vector<uint8_t> buf_;
	bool in_packet_ = false;
	size_t skipped_ = 0;
	std::deque<Dxl2Item> out_;
};

} // namespace tcs
