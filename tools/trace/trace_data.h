// A tcs trace loaded into memory as typed records, one vector per topic of
// trace/trace.h, for the summary, the plots and the Chrome export.
// Every field is checked: a message that is not what tcs writes is an error
// naming the topic and the message, never a silent zero.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "error.h"
#include "mcap_reader.h"

namespace tcs {

struct TraceController {
	int id = 0;
	std::string name;
	int64_t pid = 0;
	double cpu_scale = 1;
	std::string mode; // "cpu" or "lockstep"
	int64_t step_ns = 0;
};

struct TraceSlice {
	int controller = 0;
	int64_t v_start = 0, v_end = 0;
	int64_t charged = 0, cpu = 0;
	int64_t wall_start = 0, wall_end = 0;
	int64_t budget = -1, overshoot = 0;
	int64_t sim = 0;
	enum class End { Blocked, Preempted, Exited, Ended } end = End::Blocked;
};

struct TraceWait {
	int controller = 0;
	std::string kind;
	int64_t v_request = 0;
	int64_t deadline = -1; // -1: none
	int64_t v_end = 0;
	bool absolute = false;
	// Asked to wait for a deadline already past: a deadline miss.
	bool missed() const { return absolute && deadline >= 0 && deadline <= v_request; }
};

struct TraceCommand {
	int controller = 0;
	std::string path;
	int64_t v = 0;
	std::vector<double> values;
	bool malformed = false;
};

struct TraceStep {
	int64_t v = 0, wall = 0, wall_cost = 0;
	std::vector<double> joints; // in the order of TraceData::joint_names
};

// What went over one of the robot's wires (a /tcs/wire/ topic), counted.
struct TraceWire {
	std::string topic, kind, name; // kind: "can", "serial" or "i2c"
	uint64_t messages = 0;         // frames, runs of bytes or transfers (notes alone not counted)
	uint64_t bytes = 0;            // their data
	int64_t busy_ns = 0;           // their time on the wire (serial: the controller's way)
	int64_t busy_back_ns = 0;      // serial: the devices' way
	uint64_t refused = 0;          // what a device refused (a note), or a transfer that failed
};

struct TraceData {
	std::string path;
	bool truncated = false; // the run did not close it (killed)
	uint64_t messages = 0;
	std::vector<TraceController> controllers; // by id order
	std::vector<TraceSlice> slices;           // each controller's in time order
	std::vector<TraceWait> waits;
	std::vector<TraceCommand> commands;
	std::vector<TraceStep> steps;
	std::vector<std::string> joint_names;
	std::vector<TraceWire> wires; // in the order their first message came

	const TraceController *controller(int id) const;
	// The run's extent: the latest virtual and wall time any record shows.
	int64_t virtual_ns() const;
	int64_t wall_ns() const;
};

// Errors: the reader's, "PATH: not a tcs trace (...)", and
// "PATH: TOPIC message N: what is wrong".
Result<TraceData> load_trace(const std::string &path);

} // namespace tcs
