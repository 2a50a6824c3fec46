// The trace's wire topics (docs/DESIGN.md §6, §9): their schemas, and each
// message encoded: a topic for each CAN interface, serial line and I2C bus,
// each message one frame, run of bytes or transfer with its virtual times
// on the wire, in CDR with ROS 2 message definitions (so Foxglove and
// PlotJuggler decode them, and tcs-trace exports a CAN bus as candump's log).
#include "trace_wires.h"

#include <cstring>

#include "cdr_writer.h"

namespace tcs {

namespace {

const char kCanFrameSchema[] = R"(# tcs: a CAN frame on the bus
int64 v_start_ns # its first bit (start of frame)
int64 v_end_ns # its last, intermission included: when its receivers had it
uint32 can_id # as SocketCAN's: the identifier, CAN_EFF_FLAG 0x80000000, CAN_RTR_FLAG 0x40000000
uint8 len # data bytes (a remote frame: the length it asks for)
bool fd # a CAN FD frame
uint8 fd_flags # CANFD_BRS 1, CANFD_ESI 2
uint8[] data
string from # who sent it: a controller's socket (its program), motor N, frame 0x...
string note # what a device made of it when it refused it; else empty
)";

const char kSerialSchema[] = R"(# tcs: bytes on a serial line, sent back to back
int64 v_start_ns # the first byte's start bit
int64 v_end_ns # the last byte's stop bit: when it had arrived
uint8[] data
string from # who sent them: a controller (its program), servo N; the servos for a note alone
string note # what the devices made of them when they refused them; else empty
)";

const char kI2cSchema[] = R"(# tcs: an I2C transfer, START to STOP (I2C_RDWR, an SMBus command, a read or write)
int64 v_start_ns
int64 v_end_ns
int32 result # 0, or the negative errno the adapter returned (-6 ENXIO: no chip at the address)
tcs_msgs/I2cMessage[] messages
string from # the controller that made it (its program)
string note # why it failed; else empty
================================================================================
MSG: tcs_msgs/I2cMessage
# as struct i2c_msg: I2C_M_RD 0x1, I2C_M_TEN 0x10, ...; a read's data is what was read
uint16 addr
uint16 flags
uint8[] data
)";

// A wire message's first fields: its times on the wire.
void put_times(CdrWriter &w, int64_t v_start, int64_t v_end)
{
	const int64_t t[] = { v_start, v_end };
	std::memcpy(w.place(sizeof t, 8), t, sizeof t);
}

// Its last fields, who sent it and what a device made of it: the message's
// size.
size_t put_who(CdrWriter &w, std::string_view from, std::string_view note)
{
	w.put_string(from);
	w.put_string(note);
	return w.size();
}

void put_bytes(CdrWriter &w, std::span<const uint8_t> data)
{
	w.put_count(data.size());
	w.put_array(data.data(), data.size());
}

} // namespace

WireSchema wire_schema(TraceWireKind kind)
{
	switch (kind) {
	case TraceWireKind::can:
		return { "tcs_msgs/msg/CanFrame", kCanFrameSchema, "can" };
	case TraceWireKind::serial:
		return { "tcs_msgs/msg/SerialBytes", kSerialSchema, "serial" };
	case TraceWireKind::i2c:
		break;
	}
	return { "tcs_msgs/msg/I2cTransfer", kI2cSchema, "i2c" };
}

size_t encode_can_frame(std::string &buf, const TraceCanFrame &f)
{
	CdrWriter w(buf);
	put_times(w, f.v_start, f.v_end);
	w.put<uint32_t>(f.can_id);
	w.put<uint8_t>(uint8_t(f.data.size()));
	w.put_bool(f.fd);
	w.put<uint8_t>(f.fd_flags);
	// (A remote frame's length is what it asks for: it carries no data.)
	put_bytes(w, (f.can_id & 0x40000000u) && !f.fd ? std::span<const uint8_t>() : f.data);
	return put_who(w, f.from, f.note);
}

size_t encode_serial_bytes(std::string &buf, const TraceSerialBytes &b)
{
	CdrWriter w(buf);
	put_times(w, b.v_start, b.v_end);
	put_bytes(w, b.data);
	return put_who(w, b.from, b.note);
}

size_t encode_i2c_transfer(std::string &buf, const TraceI2cTransfer &x)
{
	CdrWriter w(buf);
	put_times(w, x.v_start, x.v_end);
	w.put<int32_t>(x.result);
	w.put_count(x.messages.size());
	for (const TraceI2cMessage &m : x.messages) {
		w.put<uint16_t>(m.addr);
		w.put<uint16_t>(m.flags);
		put_bytes(w, m.data);
	}
	return put_who(w, x.from, x.note);
}

} // namespace tcs
