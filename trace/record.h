// A record (tcs-run --record, docs/DESIGN.md §2): a trace that also holds
// what a replay needs, its settings (/tcs/record/run) and each controller's
// journal (/tcs/record/journal: every clock value it read and the time of
// every request, tcs/journal.h). Read back whole for --replay.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "error.h"
#include "tcs/journal.h"

namespace tcs {

// An actuator command in the record (its /tcs/device topic).
struct RecordedCommand {
	std::string path;
	int64_t v = 0;
	std::vector<double> values;
	bool malformed = false;
};

struct Record {
	double cpu_scale = 1.0;
	int64_t step_ns = 0;
	int64_t mono_origin_ns = 0, real_origin_ns = 0, tai_origin_ns = 0;
	std::optional<uint64_t> seed;
	uint64_t sensor_key = 0; // the sensor models' noise stream (0: none said, a record of an older tcs)
	bool slack = true;
	int64_t duration_ns = -1; // --duration; < 0: until the programs ended
	std::vector<std::string> program; // the recorded controller's command line
	std::vector<std::string> devices; // the world's devices' paths (a replay's must be the same)
	// Each controller's journal, by its number in the run (1: the first).
	std::map<int, std::vector<tcs_journal_entry>> journals;
	std::map<int, std::vector<RecordedCommand>> commands; // each controller's, in order
	std::map<int, double> scales; // each controller's CPU scale (its /tcs/controller)
	bool truncated = false; // the file stops short (the recorded run was killed)
};

// The settings as the record's JSON message.
std::string record_run_json(const Record &r);

// Reads a record. Errors: "PATH: ..." (not a file, not MCAP, damaged), or
// "PATH: not a record (a trace written without --record)".
Result<Record> read_record(const std::string &path);
// The same from bytes in memory; name stands for the path in messages.
Result<Record> read_record_bytes(std::string name, std::string bytes);

} // namespace tcs
