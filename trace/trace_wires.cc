// The trace's wire topics (docs/DESIGN.md §6, §9): a topic for each CAN
// interface, serial line and I2C bus, each message one frame, run of bytes
// or transfer with its virtual times on the wire, in CDR with ROS 2 message
// definitions (so Foxglove and PlotJuggler decode them, and tcs-trace
// exports a CAN bus as candump's log).
#include "trace.h"

#include "cdr_writer.h"

#include <cstring>

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

void put_bytes(CdrWriter &w, std::span<const uint8_t> data)
{
	w.put_count(data.size());
	w.put_array(data.data(), data.size());
}

} // namespace

Status Trace::open_wires(const std::vector<TraceWireTopic> &wires, int64_t realtime_origin_ns)
{
	wires_.clear();
	uint16_t schemas[3] = {};
	for (const TraceWireTopic &wire : wires) {
		const int k = int(wire.kind);
		if (!schemas[k]) {
			static const char *const names[] = { "tcs_msgs/msg/CanFrame", "tcs_msgs/msg/SerialBytes",
							     "tcs_msgs/msg/I2cTransfer" };
			static const char *const texts[] = { kCanFrameSchema, kSerialSchema, kI2cSchema };
			auto schema = writer_->add_schema(names[k], "ros2msg", texts[k]);
			if (!schema)
				return schema.error();
			schemas[k] = *schema;
		}
		static const char *const kinds[] = { "can", "serial", "i2c" };
		McapWriter::Metadata meta = { { "wire", kinds[k] },
					      { "name", wire.name },
					      { "realtime_origin_ns", std::to_string(realtime_origin_ns) } };
		auto channel = writer_->add_channel("/tcs/wire/" + wire.name, "cdr", schemas[k], meta);
		if (!channel)
			return channel.error();
		wires_.push_back(*channel);
	}
	return Ok{};
}

void Trace::can_frame(size_t wire, int64_t v_start, int64_t v_end, uint32_t can_id, bool fd, uint8_t fd_flags,
		      std::span<const uint8_t> data, std::string_view from, std::string_view note)
{
	if (wire >= wires_.size())
		return;
	CdrWriter w(buf_);
	const int64_t f[] = { v_start, v_end };
	std::memcpy(w.place(sizeof f, 8), f, sizeof f);
	w.put<uint32_t>(can_id);
	w.put<uint8_t>(uint8_t(data.size()));
	w.put_bool(fd);
	w.put<uint8_t>(fd_flags);
	put_bytes(w, (can_id & 0x40000000u) && !fd ? std::span<const uint8_t>() : data);
	w.put_string(from);
	w.put_string(note);
	put(wires_[wire], v_end, w.size());
}

void Trace::serial_bytes(size_t wire, int64_t v_start, int64_t v_end, std::span<const uint8_t> data,
			 std::string_view from, std::string_view note)
{
	if (wire >= wires_.size())
		return;
	CdrWriter w(buf_);
	const int64_t f[] = { v_start, v_end };
	std::memcpy(w.place(sizeof f, 8), f, sizeof f);
	put_bytes(w, data);
	w.put_string(from);
	w.put_string(note);
	put(wires_[wire], v_end, w.size());
}

void Trace::i2c_transfer(size_t wire, int64_t v_start, int64_t v_end, int32_t result,
			 std::span<const TraceI2cMessage> messages, std::string_view from, std::string_view note)
{
	if (wire >= wires_.size())
		return;
	CdrWriter w(buf_);
	const int64_t f[] = { v_start, v_end };
	std::memcpy(w.place(sizeof f, 8), f, sizeof f);
	w.put<int32_t>(result);
	w.put_count(messages.size());
	for (const TraceI2cMessage &m : messages) {
		w.put<uint16_t>(m.addr);
		w.put<uint16_t>(m.flags);
		put_bytes(w, m.data);
	}
	w.put_string(from);
	w.put_string(note);
	put(wires_[wire], v_end, w.size());
}

} // namespace tcs
