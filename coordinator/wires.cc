// The run's wires (see wires.h): reading the controllers' packets and
// stepping the buses. A packet that is not whole in a stream, too long or
// of an unknown type is the controller's mistake (or a program writing
// past the preload): its fd's input is dropped and the write fails.
#include "wires.h"

#include <sys/socket.h>

#include <cerrno>
#include <cstring>

#include "can_wire.h"
#include "i2c_wire.h"
#include "serial_wire.h"

namespace tcs {

Status Wires::bind(const WiresConfig &cfg, const SimWorld *world, WireBus::Warn warn)
{
	buses_.clear();
	for (const SerialSpec &s : cfg.serials) {
		auto bus = SerialWire::create(s, cfg.scenario_file, world, warn);
		if (!bus)
			return bus.error();
		buses_.push_back(std::move(*bus));
	}
	for (const I2cSpec &s : cfg.i2cs) {
		auto bus = I2cWire::create(s, cfg.scenario_file, world, warn, cfg.noise_key);
		if (!bus)
			return bus.error();
		buses_.push_back(std::move(*bus));
	}
	// One bus for every CAN interface: a socket may be bound to all.
	if (!cfg.cans.empty()) {
		auto bus = CanWire::create(cfg.cans, cfg.scenario_file, world, warn);
		if (!bus)
			return bus.error();
		buses_.push_back(std::move(*bus));
	}
	return Ok{};
}

std::shared_ptr<WirePort> Wires::open(size_t index)
{
	auto port = std::make_shared<WirePort>();
	port->bus = bus(index);
	if (port->bus)
		port->bus->opened(port);
	return port;
}

int64_t Wires::take(WirePort &port, int sock, int64_t v, const SimWorld *world)
{
	if (!port.bus)
		return -EBADF;
	const bool stream = port.bus->socket_type() == SOCK_STREAM;
	char buf[sizeof(tcs_wire_head) + TCS_WIRE_PAYLOAD_MAX];
	int64_t result = 0;
	for (;;) {
		ssize_t n = recv(sock, buf, sizeof buf, MSG_DONTWAIT);
		if (n <= 0)
			break;
		if (stream) {
			port.input.append(buf, (size_t)n);
		} else {
			port.input.assign(buf, (size_t)n);
			if (n < (ssize_t)sizeof(tcs_wire_head))
				result = result ? result : -EINVAL;
		}
		while (port.input.size() >= sizeof(tcs_wire_head)) {
			tcs_wire_head h;
			memcpy(&h, port.input.data(), sizeof h);
			if (h.len > TCS_WIRE_PAYLOAD_MAX || (!stream && sizeof h + h.len != port.input.size())) {
				port.input.clear();
				result = result ? result : -EINVAL;
				break;
			}
			if (port.input.size() < sizeof h + h.len)
				break; // (a stream: the rest is on its way)
			int64_t r = port.bus->take(port, h.type, std::string_view(port.input).substr(sizeof h, h.len), v, world);
			if (r < 0 && result == 0)
				result = r;
			port.input.erase(0, sizeof h + h.len);
		}
		if (!stream)
			port.input.clear();
	}
	return result;
}

void Wires::step_once(int64_t s, const SimWorld *world)
{
	if (stepped_for_ >= s || !world)
		return;
	stepped_for_ = s;
	for (auto &b : buses_)
		b->step(s, *world);
}

void Wires::advance(int64_t t, int64_t s, const SimWorld *world)
{
	if (buses_.empty())
		return;
	step_once(s, world);
	for (auto &b : buses_)
		if (b->next_event() <= t)
			b->advance(t, world);
}

int64_t Wires::next_event() const
{
	int64_t next = TCS_NEVER;
	for (const auto &b : buses_)
		next = std::min(next, b->next_event());
	return next;
}

std::vector<TraceWireTopic> Wires::trace_topics() const
{
	std::vector<TraceWireTopic> out;
	for (const auto &b : buses_)
		b->trace_topics(out);
	return out;
}

void Wires::trace_to(Trace &trace)
{
	std::vector<TraceWireTopic> topics;
	for (auto &b : buses_) {
		b->trace_to(&trace, topics.size());
		b->trace_topics(topics);
	}
}

void Wires::before_step(int64_t s, int64_t step_ns, SimWorld &world)
{
	if (buses_.empty())
		return;
	advance(s + step_ns - 1, s, &world);
	for (auto &b : buses_)
		b->apply(world);
}

} // namespace tcs
