// The world's devices as the coordinator serves them: the devices bound to
// the world's signals, the stream records made for each open instance, and
// the actuator commands written and not yet in force (docs/DESIGN.md §4). What a
// controller asks of them (DEV_OPEN, DEV_SYNC) is device_requests.cc's.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "controller.h"
#include "device.h"
#include "error.h"
#include "sim_world.h"
#include "trace.h"

namespace tcs {

class DeviceServer {
public:
	using Warn = std::function<void(const std::string &)>;
	// Each device's signals resolved in world (none: an empty world, where
	// a device is an error). Warnings (records dropped, malformed commands)
	// go to warn.
	Status bind(const std::vector<DeviceConfig> &devices, const SimWorld *world, Warn warn);
	std::vector<BoundDevice> &bound() { return devices_; }

	// Each command as it is taken (values; null: a malformed record), for
	// a replay to compare with the record's (may be empty).
	std::function<void(Controller &, const std::string &path, const std::vector<double> *values)> on_command;

	// A stream's records due before `until`, made from the world as it is.
	void make_records(OpenDevice &d, int64_t until, const SimWorld *world);
	void fill_streams(const std::vector<std::unique_ptr<Controller>> &ctls, int64_t until, const SimWorld *world);
	// The records c wrote to d, stamped c.v(); false if one was malformed.
	bool take_commands(Controller &c, OpenDevice &d, bool written_lazily, Trace &trace);
	// Those written without a round trip (lockstep), before c's time moves;
	// but for handle `except`, whose request will take them.
	void take_lazy_commands(Controller &c, int64_t except, Trace &trace);
	// The commands written by `boundary`, in the order written (the last
	// one wins), each put in force: per signal of its device, `each` gets
	// the command's time, the signal's index and its values.
	// (A template: it runs at every world step.)
	template <class F> void take_due(int64_t boundary, const SimWorld &world, F each)
	{
		while (!commands_.empty() && std::get<0>(commands_.front()) <= boundary) {
			auto &[at, dev, values] = commands_.front();
			dev->command = values;
			size_t off = 0;
			for (size_t i : dev->signals) {
				const size_t width = world.signal(i).width;
				each(at, i, dev->command.data() + off, width);
				off += width;
			}
			commands_.pop_front();
		}
	}

private:
	std::vector<BoundDevice> devices_; // (never reallocated once bound: opens point into it)
	// Actuator commands not yet in force: (virtual time, device, values).
	std::deque<std::tuple<int64_t, BoundDevice *, std::vector<double>>> commands_;
	Warn warn_;
};

// Records due on c's open sensors by its time, into their fds.
void deliver(Controller &c);
// When c's next stream record is due (TCS_NEVER: none); one waiting in
// the queue for the program to read the record before it is not.
int64_t next_record_due(const Controller &c);
// The controller has read all that d's fd held.
bool drained(const OpenDevice &d);

} // namespace tcs
