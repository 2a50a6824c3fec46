// Virtual devices on the coordinator's side: a device bound to the world's
// signals, one controller's open instance of it (the socket the controller
// reads and writes, and the stream records waiting to be due), and the
// record formats: text lines of numbers, or little-endian f64s.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tcs/device_table.h"
#include "unique_fd.h"
#include "wire_port.h"

namespace tcs {

struct DeviceConfig {
	std::string path;
	int kind = TCS_DEVICE_SENSOR;   // or TCS_DEVICE_ACTUATOR
	int format = TCS_FORMAT_TEXT;   // or TCS_FORMAT_BINARY
	bool latest = false;            // sensor: every read returns the current value
	int64_t period_ns = 0;          // stream sensor: one record per period
	std::optional<double> limit;    // actuator: saturation
	std::vector<std::string> signals;
	size_t wire = 0;                // a wire (TCS_DEVICE_SERIAL...): its bus among Wires'
	uint32_t table_width = 0;       // a wire: the device table's width (a line's baud, a CAN MTU)
};

// A device whose signals are resolved in the world.
struct BoundDevice {
	DeviceConfig cfg;
	std::vector<size_t> signals; // world signal indices
	size_t width = 0;            // values per record
	std::vector<double> command; // actuator: the last valid command
	uint64_t malformed = 0;      // actuator: records rejected
};

// One controller's open instance of a device.
struct OpenDevice {
	BoundDevice *dev = nullptr;
	UniqueFd sock;              // our end of the controller's fd
	int64_t next_due = 0;       // stream: due time of the next record to make
	std::deque<std::pair<int64_t, std::string>> queue; // stream records made, not yet due
	uint64_t dropped = 0;       // stream records dropped because nobody read them
	std::string input;          // actuator: bytes of an incomplete record
	bool gone = false;          // the controller closed it
	std::shared_ptr<WirePort> wire; // a wire's fd: its port on the bus
};

// Whether a device kind is one of the robot's wires (serial, I2C, CAN).
inline bool is_wire(int kind)
{
	return kind == TCS_DEVICE_SERIAL || kind == TCS_DEVICE_I2C || kind == TCS_DEVICE_CAN;
}

// One record of values in the device's format.
std::string format_record(int format, const std::vector<double> &values);

// Takes every complete record out of input (what is left is an incomplete
// one) and appends its values to records. Returns false at the first
// malformed record, with a reason; the records before it are kept.
bool parse_records(int format, size_t width, std::string &input, std::vector<std::vector<double>> &records,
		   std::string *why);

} // namespace tcs
