// The CAN interfaces, their motors and frames in virtual time (see
// can_wire.h); what reaches the sockets is can_ports.cc's.
#include "can_wire.h"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace tcs {

namespace {

constexpr uint64_t kMaxNotes = 20;

std::string hex_id(uint32_t id)
{
	char buf[16];
	snprintf(buf, sizeof buf, "0x%X", id);
	return buf;
}

CanType can_type_of(const std::string &name)
{
	static const std::pair<const char *, CanType> types[] = {
		{ "int8", CanType::int8 },     { "int16", CanType::int16 },   { "int32", CanType::int32 },
		{ "uint8", CanType::uint8 },   { "uint16", CanType::uint16 }, { "uint32", CanType::uint32 },
		{ "float32", CanType::float32 },
	};
	for (const auto &[n, t] : types)
		if (name == n)
			return t;
	return CanType::uint8; // (the scenario accepts only the names above)
}

// The fields of a [[can.frame]] as can_layout takes them.
std::vector<CanField> fields_of(const CanFrameSpec &f)
{
	std::vector<CanField> out;
	for (const CanFieldSpec &s : f.fields) {
		CanField c;
		c.name = s.signal.name;
		c.type = can_type_of(s.type);
		c.scale = s.scale;
		c.offset = s.offset;
		c.order = f.big_endian ? CanByteOrder::big : CanByteOrder::little;
		c.start = s.start;
		out.push_back(std::move(c));
	}
	return out;
}

} // namespace

Result<std::unique_ptr<CanWire>> CanWire::create(const std::vector<CanSpec> &specs, const std::string &scenario_file,
						 const SimWorld *world, Warn warn)
{
	std::unique_ptr<CanWire> w(new CanWire(std::move(warn)));
	auto where = [&](int line) { return scenario_file + ":" + std::to_string(line) + ": "; };
	uint32_t world_source = kCanWorldSources;
	// A "<model>.<part>.<field>[N]" signal of the world.
	auto value_of = [&](const SignalRef &ref, Value *out) -> Status {
		std::string name = ref.name;
		out->index = 0;
		if (size_t open = name.find('['); open != std::string::npos) {
			out->index = std::atoi(name.c_str() + open + 1);
			name.resize(open);
		}
		if (!world)
			return Ok{};
		long i = world->find(name);
		if (i < 0)
			return Error{ where(ref.line) + "unknown signal '" + name + "'" };
		out->signal = size_t(i);
		return Ok{};
	};
	for (size_t k = 0; k < specs.size(); k++) {
		const CanSpec &spec = specs[k];
		Iface f(spec.bitrate, spec.data_bitrate);
		f.name = spec.interface;
		f.ifindex = int32_t(TCS_CAN_IFINDEX_BASE + k);
		f.fd = spec.data_bitrate > 0;
		for (const CanMotorSpec &m : spec.motors) {
			MitRanges r{ m.position_range, m.velocity_range, m.torque_range, m.kp_max, m.kd_max };
			Motor motor(MitMotor(uint8_t(m.id), r, m.reply_id));
			motor.source = world_source++;
			if (world) {
				long p = world->find(m.joint.name + ".position"), v = world->find(m.joint.name + ".velocity"),
				     e = world->find(m.joint.name + ".effort");
				if (p < 0 || v < 0 || e < 0)
					return Error{ where(m.joint.line) + "unknown joint '" + m.joint.name + "'" };
				motor.position = size_t(p), motor.velocity = size_t(v), motor.effort = size_t(e);
			}
			f.motors.push_back(std::move(motor));
		}
		for (const CanFrameSpec &fr : spec.frames) {
			auto layout = can_layout(fields_of(fr), f.fd);
			if (!layout)
				return Error{ where(fr.line) + layout.error().message };
			std::vector<Value> values(fr.fields.size());
			for (size_t i = 0; i < fr.fields.size(); i++)
				if (Status s = value_of(fr.fields[i].signal, &values[i]); !s)
					return s.error();
			if (fr.command) {
				CommandFrame c;
				c.layout = std::move(*layout);
				c.id = fr.id, c.extended = fr.extended;
				c.efforts = std::move(values);
				c.held.assign(c.efforts.size(), 0.0);
				f.commands.push_back(std::move(c));
			} else {
				SensorFrame s;
				s.layout = std::move(*layout);
				s.id = fr.id, s.extended = fr.extended;
				s.period_ns = std::max<int64_t>(fr.period_ns, 1);
				s.values = std::move(values);
				s.source = world_source++;
				f.sensors.push_back(std::move(s));
			}
		}
		w->ifaces_.push_back(std::move(f));
	}
	return w;
}

int CanWire::socket_type() const
{
	return SOCK_SEQPACKET;
}

void CanWire::opened(const std::shared_ptr<WirePort> &port)
{
	std::erase_if(ports_, [](const std::weak_ptr<WirePort> &p) { return p.expired(); });
	port->can_source = next_source_++;
	if (next_source_ >= kCanWorldSources)
		next_source_ = 1; // (two billion sockets later: an old number again)
	ports_.push_back(port);
}

void CanWire::note(const std::string &what)
{
	if (++notes_ <= kMaxNotes)
		warn_(what + (notes_ == kMaxNotes ? " (further notes not shown)" : ""));
}

CanWire::Iface *CanWire::iface_of(int32_t ifindex)
{
	for (Iface &f : ifaces_)
		if (f.ifindex == ifindex)
			return &f;
	return nullptr;
}

// TCS_WIRE_DATA: the interface (0: the bound one) and the frame, as
// raw_sendmsg takes them.
int64_t CanWire::send(WirePort &port, std::string_view payload, int64_t v)
{
	int32_t ifindex = 0;
	if (payload.size() < sizeof ifindex)
		return -EINVAL;
	memcpy(&ifindex, payload.data(), sizeof ifindex);
	payload.remove_prefix(sizeof ifindex);
	if (ifindex == 0)
		ifindex = port.ifindex;
	Iface *f = ifindex > 0 ? iface_of(ifindex) : nullptr;
	if (!f)
		return -ENXIO;
	auto frame = frame_from_linux(payload.data(), payload.size(), port.fd_frames && f->fd);
	if (!frame)
		return -EINVAL;
	if (!f->bus.submit(port.can_source, *frame, v))
		return -ENOBUFS;
	f->loopback[port.can_source].push_back(port.loopback);
	return 0;
}

int64_t CanWire::take(WirePort &port, uint32_t type, std::string_view payload, int64_t v, const SimWorld *world)
{
	if (type == TCS_WIRE_DATA)
		return send(port, payload, v);
	if (type == TCS_WIRE_BIND) {
		int32_t ifindex = 0;
		if (payload.size() != sizeof ifindex)
			return -EINVAL;
		memcpy(&ifindex, payload.data(), sizeof ifindex);
		if (ifindex != 0 && !iface_of(ifindex))
			return -ENODEV;
		port.ifindex = ifindex;
		return 0;
	}
	if (type == TCS_WIRE_CANOPT) {
		tcs_wire_canopt opt;
		if (payload.size() < sizeof opt)
			return -EINVAL;
		memcpy(&opt, payload.data(), sizeof opt);
		return can_set_option(port, opt.level, opt.name, payload.substr(sizeof opt));
	}
	return -EINVAL;
}

int64_t CanWire::next_on(const Iface &f) const
{
	int64_t next = TCS_NEVER;
	for (const SensorFrame &s : f.sensors)
		next = std::min(next, s.next_due);
	if (auto end = f.bus.next_end())
		next = std::min(next, *end);
	// A frame that starts leaves its socket's queue: the bus is advanced
	// then, not only at the end of the frame before it (else the frame on
	// the wire would hold a place in the queue until that end).
	if (auto start = f.bus.next_start())
		next = std::min(next, *start);
	return next;
}

int64_t CanWire::next_event() const
{
	int64_t next = TCS_NEVER;
	for (const Iface &f : ifaces_)
		next = std::min(next, next_on(f));
	return next;
}

// The sensor frames due by t, packed from the world now.
void CanWire::send_sensors(Iface &f, int64_t t, const SimWorld *world)
{
	std::vector<double> values, all;
	for (SensorFrame &s : f.sensors) {
		if (s.next_due > t)
			continue;
		values.clear();
		for (const Value &v : s.values) {
			all.clear();
			if (world)
				world->read(v.signal, all);
			values.push_back(size_t(v.index) < all.size() ? all[size_t(v.index)] : 0.0);
		}
		CanFrame frame;
		can_pack(s.layout, values.data(), frame);
		frame.id = s.id;
		frame.extended = s.extended;
		if (f.bus.submit(s.source, frame, s.next_due))
			f.loopback[s.source].push_back(false);
		else
			note(f.name + ": sensor frame " + hex_id(s.id) + " dropped: its queue is full");
		s.next_due += s.period_ns;
	}
}

// A frame has ended on f: the sockets, the motors and the command frames
// take it.
void CanWire::delivered(Iface &f, const CanDelivery &d, const SimWorld *world)
{
	std::string notes; // what the devices made of it
	bool loopback = false;
	if (auto q = f.loopback.find(d.source); q != f.loopback.end() && !q->second.empty()) {
		loopback = q->second.front();
		q->second.pop_front();
		if (q->second.empty())
			f.loopback.erase(q);
	}
	can_deliver(ports_, f.ifindex, d, loopback);
	std::vector<double> values;
	for (Motor &m : f.motors) {
		if (m.source == d.source)
			continue;
		double p = 0, v = 0;
		if (world) {
			values.clear();
			world->read(m.position, values);
			world->read(m.velocity, values);
			if (values.size() >= 2)
				p = values[0], v = values[1];
		}
		std::string why;
		auto reply = m.motor.receive(d.frame, p, v, m.torque, &why);
		if (!why.empty()) {
			note(f.name + ": " + why); // ("motor N: ...")
			notes += (notes.empty() ? "" : "; ") + why;
		}
		if (reply && f.bus.submit(m.source, *reply, d.end_ns))
			f.loopback[m.source].push_back(false);
	}
	for (CommandFrame &c : f.commands) {
		if (d.frame.id != c.id || d.frame.extended != c.extended || d.frame.rtr)
			continue;
		std::string why;
		if (can_unpack(c.layout, d.frame, c.held, &why)) {
			c.received = true;
		} else {
			note(f.name + ": command frame " + hex_id(c.id) + ": " + why);
			notes += (notes.empty() ? "" : "; ") + ("command frame " + hex_id(c.id) + ": " + why);
		}
	}
	if (trace_) {
		const CanFrame &fr = d.frame;
		const uint32_t can_id = fr.id | (fr.extended ? CAN_EFF_FLAG : 0) | (fr.rtr ? CAN_RTR_FLAG : 0);
		const uint8_t flags = uint8_t((fr.brs ? CANFD_BRS : 0) | (fr.esi ? CANFD_ESI : 0));
		const std::string from = sender(f, d.source);
		trace_->can_frame(topic_ + size_t(&f - ifaces_.data()), { .v_start = d.start_ns,
									  .v_end = d.end_ns,
									  .can_id = can_id,
									  .fd = fr.fd,
									  .fd_flags = flags,
									  .data = { fr.data, fr.len },
									  .from = from,
									  .note = notes });
	}
}

std::string CanWire::sender(const Iface &f, uint32_t source) const
{
	for (const Motor &m : f.motors)
		if (m.source == source)
			return "motor " + std::to_string(m.motor.id());
	for (const SensorFrame &s : f.sensors)
		if (s.source == source)
			return "frame " + hex_id(s.id);
	for (const auto &wp : ports_)
		if (auto p = wp.lock(); p && p->can_source == source)
			return p->owner;
	return "a closed socket";
}

void CanWire::trace_topics(std::vector<TraceWireTopic> &out) const
{
	for (const Iface &f : ifaces_)
		out.push_back({ TraceWireKind::can, f.name });
}

void CanWire::advance(int64_t t, const SimWorld *world)
{
	for (Iface &f : ifaces_) {
		for (;;) {
			int64_t due = TCS_NEVER;
			for (const SensorFrame &s : f.sensors)
				due = std::min(due, s.next_due);
			const auto end = f.bus.next_end();
			const int64_t e = end ? *end : TCS_NEVER;
			// A sensor frame ready by the bus's next end contends for it.
			if (due <= t && due <= e) {
				send_sensors(f, due, world);
				continue;
			}
			if (e > t)
				break;
			for (const CanDelivery &d : f.bus.advance(e))
				delivered(f, d, world);
		}
		for (const CanDelivery &d : f.bus.advance(t)) // (what started by t is on the wire)
			delivered(f, d, world);
	}
}

void CanWire::step(int64_t s, const SimWorld &world)
{
	std::vector<double> values;
	for (Iface &f : ifaces_)
		for (Motor &m : f.motors) {
			values.clear();
			world.read(m.position, values);
			world.read(m.velocity, values);
			m.torque = values.size() >= 2 ? m.motor.torque(values[0], values[1]) : 0.0;
		}
	(void)s;
}

void CanWire::apply(SimWorld &world)
{
	std::vector<double> values;
	for (Iface &f : ifaces_) {
		for (const Motor &m : f.motors)
			world.write(m.effort, &m.torque);
		for (const CommandFrame &c : f.commands) {
			if (!c.received)
				continue;
			for (size_t i = 0; i < c.efforts.size(); i++) {
				values.clear();
				world.read(c.efforts[i].signal, values);
				const size_t at = size_t(std::max(c.efforts[i].index, 0));
				if (at >= values.size())
					continue;
				values[at] = c.held[i];
				world.write(c.efforts[i].signal, values.data());
			}
		}
	}
}

} // namespace tcs
