// A serial line and its servos in virtual time (see serial_wire.h).
#include "serial_wire.h"

#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "dynamixel_items.h"

namespace tcs {

namespace {

// 8N1, what a Dynamixel line uses.
constexpr int kFrameBits = 10;
// Notes on what the servos refused or ignored: the first few are logged
// (a controller in a loop would flood the log), the count at the end.
constexpr uint64_t kMaxNotes = 20;

} // namespace

SerialWire::SerialWire(const SerialSpec &spec, Warn warn)
	: spec_(spec), warn_(std::move(warn)), ctl_baud_(spec.baud), to_servos_(spec.baud, kFrameBits),
	  to_controller_(spec.baud, kFrameBits)
{
}

Result<std::unique_ptr<SerialWire>> SerialWire::create(const SerialSpec &spec, const std::string &scenario_file,
						       const SimWorld *world, Warn warn)
{
	std::unique_ptr<SerialWire> w(new SerialWire(spec, std::move(warn)));
	auto where = [&](int line) { return scenario_file + ":" + std::to_string(line) + ": "; };
	w->step_ns_ = world ? world->step_ns() : 0;
	for (const ServoSpec &s : spec.servos) {
		if (Status st = w->chain_.add(uint8_t(s.id)); !st)
			return Error{ where(s.line) + st.error().message };
		// The servo's rate is the line's: Baud Rate (8) set to match.
		DynamixelServo &servo = w->chain_.servo(w->chain_.size() - 1);
		uint8_t code = 0;
		while (code < 8 && servo.baud() != spec.baud) {
			(void)servo.write(kDxlBaudRate, &code, 1, DxlAddressing::id);
			code++;
		}
		if (servo.baud() != spec.baud) // (the scenario's parser refuses it first)
			return Error{ where(spec.line) + "baud " + std::to_string(spec.baud) +
				      " is not a rate of a Dynamixel X servo" };
		Joint j;
		if (world) {
			long p = world->find(s.joint.name + ".position"), v = world->find(s.joint.name + ".velocity"),
			     e = world->find(s.joint.name + ".effort");
			if (p < 0 || v < 0 || e < 0)
				return Error{ where(s.joint.line) + "unknown joint '" + s.joint.name + "'" };
			j.position = size_t(p), j.velocity = size_t(v), j.effort = size_t(e);
		}
		w->joints_.push_back(j);
	}
	return w;
}

int SerialWire::socket_type() const
{
	return SOCK_STREAM;
}

void SerialWire::opened(const std::shared_ptr<WirePort> &port)
{
	std::erase_if(ports_, [](const std::weak_ptr<WirePort> &p) { return p.expired(); });
	ports_.push_back(port);
}

void SerialWire::note(const std::string &what)
{
	if (++notes_ <= kMaxNotes)
		warn_(spec_.path + ": " + what + (notes_ == kMaxNotes ? " (further notes not shown)" : ""));
}

int64_t SerialWire::take(WirePort &port, uint32_t type, std::string_view payload, int64_t v, const SimWorld *world)
{
	if (type == TCS_WIRE_LINE) {
		tcs_wire_line line;
		if (payload.size() != sizeof line)
			return -EINVAL;
		memcpy(&line, payload.data(), sizeof line);
		if (line.baud == 0 || line.baud > 100000000 || line.bits_per_byte < 7 || line.bits_per_byte > 12)
			return -EINVAL;
		ctl_baud_ = line.baud;
		to_servos_.set_baud(line.baud, int(line.bits_per_byte));
		to_controller_.set_baud(line.baud, int(line.bits_per_byte));
		return 0;
	}
	if (type != TCS_WIRE_DATA)
		return -EINVAL;
	if (payload.empty())
		return 0;
	const int64_t start = std::max(v, to_servos_.idle_at());
	const int64_t end = to_servos_.send(payload.size(), v);
	if (trace_)
		trace_->serial_bytes(topic_, { .v_start = start,
					       .v_end = end,
					       .data = { reinterpret_cast<const uint8_t *>(payload.data()), payload.size() },
					       .from = port.owner });
	in_flight_.insert(in_flight_.end(), payload.begin(), payload.end());
	return 0;
}

int64_t SerialWire::next_event() const
{
	return to_servos_.pending() > 0 ? to_servos_.arrival(0) : TCS_NEVER;
}

// The servos' answers on the line back, each byte to every fd open on it
// when it has arrived.
void SerialWire::answer(std::vector<DxlReply> replies, int64_t end)
{
	int64_t t = end;
	for (const DxlReply &r : replies) {
		const size_t first = to_controller_.pending();
		const int64_t start = std::max(t + r.delay_ns, to_controller_.idle_at());
		t = to_controller_.send(r.bytes.size(), t + r.delay_ns);
		if (trace_)
			trace_->serial_bytes(topic_, { .v_start = start, .v_end = t, .data = r.bytes,
						       .from = "servo " + std::to_string(r.id) });
		for (size_t i = 0; i < r.bytes.size(); i++) {
			const int64_t due = to_controller_.arrival(first + i);
			for (auto &wp : ports_)
				if (auto p = wp.lock())
					p->push(due, std::string(1, char(r.bytes[i])));
		}
	}
	// (What was sent is counted here until taken: the content went out.)
	to_controller_.take(t);
}

void SerialWire::advance(int64_t t, const SimWorld *world)
{
	std::vector<std::string> notes;
	while (to_servos_.pending() > 0 && to_servos_.arrival(0) <= t) {
		const int64_t at = to_servos_.arrival(0);
		const uint8_t b = in_flight_.front();
		in_flight_.pop_front();
		to_servos_.take(at);
		parser_.feed(&b, 1);
		Dxl2Item item;
		while (parser_.next(item)) {
			std::vector<DxlReply> replies;
			if (auto *p = std::get_if<Dxl2Packet>(&item))
				replies = chain_.handle(*p, ctl_baud_, &notes);
			else
				replies = chain_.handle(std::get<Dxl2Fault>(item), ctl_baud_, &notes);
			answer(std::move(replies), at);
			for (const std::string &n : notes) {
				note(n);
				if (trace_) // (at the byte that ended the packet)
					trace_->serial_bytes(topic_,
							     { .v_start = at, .v_end = at, .from = "servos", .note = n });
			}
			notes.clear();
		}
	}
}

void SerialWire::step(int64_t s, const SimWorld &world)
{
	std::vector<double> values;
	const double dt = double(step_ns_) * 1e-9;
	for (size_t i = 0; i < joints_.size(); i++) {
		Joint &j = joints_[i];
		values.clear();
		world.read(j.position, values);
		world.read(j.velocity, values);
		j.torque = chain_.servo(i).step(values[0], values[1], dt);
	}
}

void SerialWire::apply(SimWorld &world)
{
	for (const Joint &j : joints_)
		world.write(j.effort, &j.torque);
}

void SerialWire::trace_topics(std::vector<TraceWireTopic> &out) const
{
	out.push_back({ TraceWireKind::serial, wire_topic_name(spec_.path) });
}

int64_t SerialWire::drained_at(const WirePort &) const
{
	return to_servos_.idle_at();
}

} // namespace tcs
