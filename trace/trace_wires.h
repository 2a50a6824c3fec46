// The trace's wire topics (docs/DESIGN.md §6, §9): one for each CAN
// interface, serial line and I2C bus of the run, /tcs/wire/<name>; what
// goes over a wire, and its messages' schemas and CDR encoding.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace tcs {

enum class TraceWireKind { can, serial, i2c };

// A wire of the run: name "can0", "dev/ttyUSB0", "dev/i2c-1".
struct TraceWireTopic {
	TraceWireKind kind;
	std::string name;
};

// Each from v_start (its first bit on the wire) to v_end (its last: when
// its receivers had it); from: who sent it; note: what a device made of
// it, when it refused it.
struct TraceCanFrame {
	int64_t v_start = 0, v_end = 0;
	uint32_t can_id = 0; // as SocketCAN's: CAN_EFF_FLAG, CAN_RTR_FLAG
	bool fd = false;
	uint8_t fd_flags = 0; // CANFD_BRS, CANFD_ESI
	std::span<const uint8_t> data; // len bytes (a remote frame's: its length)
	std::string_view from, note;
};

struct TraceSerialBytes {
	int64_t v_start = 0, v_end = 0;
	std::span<const uint8_t> data;
	std::string_view from, note;
};

// A message of an I2C transfer, as struct i2c_msg (a read's data: what was
// read).
struct TraceI2cMessage {
	uint16_t addr = 0, flags = 0;
	std::span<const uint8_t> data;
};

struct TraceI2cTransfer {
	int64_t v_start = 0, v_end = 0;
	int32_t result = 0; // 0, or the adapter's negative errno
	std::span<const TraceI2cMessage> messages;
	std::string_view from, note;
};

// A kind's schema: its ROS 2 name and definition, and the kind's name in
// its channels' metadata ("wire").
struct WireSchema {
	const char *name, *definition, *kind;
};
WireSchema wire_schema(TraceWireKind kind);

// Each message encoded into buf (CDR, as CdrWriter: buf only ever grown):
// its size.
size_t encode_can_frame(std::string &buf, const TraceCanFrame &f);
size_t encode_serial_bytes(std::string &buf, const TraceSerialBytes &b);
size_t encode_i2c_transfer(std::string &buf, const TraceI2cTransfer &x);

} // namespace tcs
