// The scenario's SocketCAN interfaces as the coordinator drives them
// (docs/DESIGN.md §9): one WireBus for all of them, since a CAN_RAW socket
// may be bound to any interface, or to every one (ifindex 0), and may send
// on any with sendto. Each interface is a CanBus (arbitration, bit times)
// with its MIT motors and its frames of signals. A frame reaches the
// sockets bound to its interface when its last bit has (its end), filtered
// as the kernel's CAN_RAW filters it (can_ports.cc); the motors answer on
// the bus at that time; the world's sensor frames go out at their rate.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "can_bus.h"
#include "can_ports.h"
#include "can_signals.h"
#include "error.h"
#include "mit_motor.h"
#include "scenario.h"
#include "wire_bus.h"

namespace tcs {

class CanWire final : public WireBus {
public:
	static Result<std::unique_ptr<CanWire>> create(const std::vector<CanSpec> &specs,
						       const std::string &scenario_file, const SimWorld *world,
						       Warn warn);
	int socket_type() const override;
	void opened(const std::shared_ptr<WirePort> &port) override;
	int64_t take(WirePort &port, uint32_t type, std::string_view payload, int64_t v, const SimWorld *world) override;
	int64_t next_event() const override;
	void advance(int64_t t, const SimWorld *world) override;
	void step(int64_t s, const SimWorld &world) override;
	void apply(SimWorld &world) override;
	void trace_topics(std::vector<TraceWireTopic> &out) const override;

private:
	// A world signal's value: the signal, and which of its values.
	struct Value {
		size_t signal = 0;
		int index = 0; // -1 in the scenario: the first
	};
	struct Motor {
		explicit Motor(MitMotor m) : motor(m) {}
		MitMotor motor;
		size_t position = 0, velocity = 0, effort = 0;
		double torque = 0; // this step's
		uint32_t source = 0;
	};
	struct SensorFrame {
		CanLayout layout;
		uint32_t id = 0;
		bool extended = false;
		int64_t period_ns = 0, next_due = 0;
		std::vector<Value> values;
		uint32_t source = 0;
	};
	struct CommandFrame {
		CanLayout layout;
		uint32_t id = 0;
		bool extended = false;
		std::vector<Value> efforts;
		std::vector<double> held; // the last values received, one a field
		bool received = false;
	};
	struct Iface {
		Iface(int64_t bitrate, int64_t data_bitrate) : bus(bitrate, data_bitrate ? data_bitrate : bitrate) {}
		std::string name;
		int32_t ifindex = 0;
		bool fd = false;
		CanBus bus;
		std::vector<Motor> motors;
		std::vector<SensorFrame> sensors;
		std::vector<CommandFrame> commands;
		// Each source's queued frames' loopback (the sender's socket's
		// CAN_RAW_LOOPBACK when it sent): a source's frames never reorder.
		std::map<uint32_t, std::deque<bool>> loopback;
	};

	explicit CanWire(Warn warn) : warn_(std::move(warn)) {}
	Iface *iface_of(int32_t ifindex);
	void note(const std::string &what);
	int64_t send(WirePort &port, std::string_view payload, int64_t v);
	// The next thing due on iface: a sensor frame's time or its bus's
	// next frame end.
	int64_t next_on(const Iface &f) const;
	void send_sensors(Iface &f, int64_t t, const SimWorld *world);
	void delivered(Iface &f, const CanDelivery &d, const SimWorld *world);
	// Who sent what source queued, for the trace.
	std::string sender(const Iface &f, uint32_t source) const;

	Warn warn_;
	std::vector<Iface> ifaces_;
	std::vector<std::weak_ptr<WirePort>> ports_;
	uint32_t next_source_ = 1; // the ports'; the world's from 0x80000000
	uint64_t notes_ = 0;
};

} // namespace tcs
