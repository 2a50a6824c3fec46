// DynamixelChain: the servos on one serial line, and what a packet from
// the controller makes them do: which of them hear it, which answer, and
// in what order their status packets go on the wire.
//
// Every servo at the line's baud that speaks Protocol 2.0 hears every
// packet (the Bus Watchdog counts from it). A packet to an ID no servo has
// goes unanswered. To the broadcast ID: every servo executes it and none
// answers but for PING, which each answers in turn (ascending ID; the
// e-Manual's "arranged order"). SYNC_READ and BULK_READ are answered by
// each servo they list, in the packet's order, each after the previous
// answer ended and its own Return Delay Time; a servo not on the chain is
// skipped, as is a second listing of the same ID (the e-Manual allows one).
// A SYNC/BULK packet whose params do not divide into whole entries is
// ignored by all. A packet with a bad CRC gets, from the servo of its ID
// (not the broadcast ID), a status with the CRC Error (0x03), as far as
// its Status Return Level allows for the instruction byte received: the
// e-Manual's status errors include it ("CRC of the sent Packet does not
// match"), and a servo that knew nothing of the packet would have no use
// for that error number.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dynamixel2_parser.h"
#include "dynamixel_servo.h"
#include "error.h"
#include "serial_line.h"

namespace tcs {

// A status packet to send, in the order they go on the wire.
struct DxlReply {
	uint8_t id = 0; // the servo answering
	// Its Return Delay Time: the reply starts this long after the previous
	// reply ended (the first: after the instruction packet's last byte).
	int64_t delay_ns = 0;
	std::vector<uint8_t> bytes;
};

class DynamixelChain {
public:
	// A servo at factory settings with this ID; refused for an ID above
	// 252 or one already on the chain.
	Status add(uint8_t id);

	size_t size() const { return servos_.size(); }
	// In the order added (IDs may change since: a WRITE to ID(7)).
	DynamixelServo &servo(size_t i) { return servos_[i]; }
	const DynamixelServo &servo(size_t i) const { return servos_[i]; }

	// A packet from the controller, at line_baud bit/s (0: any). Notes
	// (one line each, for the log) say what was refused or ignored.
	std::vector<DxlReply> handle(const Dxl2Packet &p, int64_t line_baud = 0,
				     std::vector<std::string> *notes = nullptr);
	// A packet the parser dropped: only a bad CRC is answered.
	std::vector<DxlReply> handle(const Dxl2Fault &f, int64_t line_baud = 0,
				     std::vector<std::string> *notes = nullptr);

private:
	bool hears(const DynamixelServo &s, int64_t line_baud) const;
	void sync_read(const Dxl2Packet &p, int64_t baud, std::vector<DxlReply> &out, std::vector<std::string> *notes);
	void sync_write(const Dxl2Packet &p, int64_t baud, std::vector<std::string> *notes);
	void bulk_read(const Dxl2Packet &p, int64_t baud, std::vector<DxlReply> &out, std::vector<std::string> *notes);
	void bulk_write(const Dxl2Packet &p, int64_t baud, std::vector<std::string> *notes);
	// Reads n bytes at addr of each servo of ID id, for SYNC/BULK_READ.
	void read_of(uint8_t id, uint16_t addr, size_t n, int64_t baud, std::vector<DxlReply> &out,
		     std::vector<std::string> *notes);
	void write_to(uint8_t id, uint16_t addr, const uint8_t *data, size_t n, int64_t baud,
		      std::vector<std::string> *notes);

	std::vector<DynamixelServo> servos_;
};

// Puts the replies on the line back to the controller, the first after the
// instruction packet's end at instruction_end_ns; returns when each has
// arrived.
std::vector<int64_t> dxl_send_replies(const std::vector<DxlReply> &replies, int64_t instruction_end_ns,
				      SerialDirection &to_controller);

} // namespace tcs
