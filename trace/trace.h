// The run's trace (docs/DESIGN.md §6): an MCAP file, logged at virtual time,
// of messages Foxglove and PlotJuggler decode: those written every cycle in
// CDR with ROS 2 message definitions, the few others JSON with JSON Schemas.
// Topics: /tcs/controller (each controller: name, pid, CPU scale, mode),
// /tcs/slice (each stretch a controller ran: virtual and wall start and end,
// CPU charged and used, the budget and its overshoot when preempted, why it
// ended), /tcs/wait (each hooked wait: kind, requested deadline, when it
// ended), /tcs/device (each command written to an actuator), /tcs/step (each
// simulation step: wall time, wall cost, joint states) and /clock (the
// simulation clock, as ROS 2 publishes it); a record adds /tcs/record/run and
// /tcs/record/journal (trace/record.h); each of the robot's wires has its own,
// /tcs/wire/<name> (trace_wires.h). Wall times count from the start of the
// run.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "error.h"
#include "mcap_writer.h"
#include "tcs/journal.h"
#include "trace_wires.h"

namespace tcs {

// How a trace is written. Each message is encoded (CDR: a few stores) where
// it happens, on the caller's thread, and staged; then either written into
// the file by the caller too, in its idle moments (by_caller: pump(); chunks
// uncompressed, some hundred instructions a message and a write(2) a
// megabyte), or taken by a thread of the trace's own, kept off the
// coordinator's core (avoid_cpu; -1: anywhere), which compresses the chunks
// with zstd. The coordinator writes itself where it polls on a core of its
// own: a thread could run there only while it sleeps (two cores: the
// controller's and the coordinator's, each spinning while the other works,
// docs/PERFORMANCE.md).
struct TraceWriting {
	bool by_caller = false;
	int avoid_cpu = -1;
};

class Trace {
public:
	// Opens path. A record (--record) has the record's topics too; each
	// wire its own, with the run's CLOCK_REALTIME origin (what a frame's
	// receive timestamp adds to its virtual time) in its metadata.
	Status open(const std::string &path, TraceWriting how = TraceWriting{}, bool record = false,
		    const std::vector<TraceWireTopic> &wires = {}, int64_t realtime_origin_ns = 0);
	bool is_open() const { return open_; }
	Status close();
	// By the caller: writes what is staged into the file, a few messages
	// at a time (false: nothing was waiting). Some hundred instructions a
	// message; now and then a chunk's write(2).
	bool pump();

	// Once per controller, before its first slice; again when a child
	// execs another program (the same id and pid, its new name).
	void controller(int controller, const std::string &name, int pid, double cpu_scale, int mode,
			int64_t step_ns);
	struct Slice {
		int64_t v_start, v_end;
		int64_t charged_ns;         // virtual CPU charged
		int64_t cpu_ns;             // real CPU the process used, hooks included
		int64_t wall_start, wall_end;
		int64_t budget_ns = -1;     // preempted: the real CPU it was given
		int64_t overshoot_ns = 0;   // preempted: real CPU used beyond the budget
		int64_t sim_ns;             // the world's time when it ended
		const char *why;            // blocked, preempted, exited, ended (the run did)
	};
	void slice(int controller, const Slice &s);
	void wait(int controller, const char *kind, int64_t v_request, int64_t deadline, int64_t v_end, bool absolute);
	void command(int controller, std::string_view path, int64_t v, std::span<const double> values, bool malformed);
	// The joint states each step records: their names, set once, then
	// their values, in that order, with each step.
	void set_joint_names(std::vector<std::string> names);
	void step(int64_t v, int64_t wall_ns, int64_t wall_cost_ns, std::span<const double> joint_values);
	// A record (--record, trace/record.h): the run's settings a replay
	// needs, once, as JSON; and each controller's journal, in batches.
	void record_run(const std::string &json);
	void journal(int controller, std::span<const tcs_journal_entry> entries);

	// What went over wire (its index in open()'s list).
	void can_frame(size_t wire, const TraceCanFrame &f);
	void serial_bytes(size_t wire, const TraceSerialBytes &b);
	void i2c_transfer(size_t wire, const TraceI2cTransfer &x);

private:
	Status open_wires(const std::vector<TraceWireTopic> &wires, int64_t realtime_origin_ns);
	// The message in buf_ (its first size bytes), logged at v: staged.
	void put(uint16_t channel, int64_t v, size_t size);
	// Writes the staged message at *at into the file, *at moved past it.
	void write_staged(const std::vector<char> &staged, size_t *at);
	void writer_loop(int avoid_cpu);

	// The caller's, or the writer thread's once it runs.
	std::optional<McapWriter> writer_;
	bool open_ = false;
	uint16_t controller_ = 0, slice_ = 0, wait_ = 0, device_ = 0, step_ = 0, clock_ = 0;
	uint16_t record_run_ = 0, journal_ = 0; // a record's
	std::vector<uint16_t> wires_;           // each wire's channel
	std::vector<std::string> joint_names_;
	// The names' part of a step message (their count and strings), as
	// CDR lays it out after the step's three times: the same every step.
	std::string step_names_;
	std::string buf_; // the message being encoded (only ever grown)

	bool by_caller_ = false;
	// The messages not yet written, one after another, each its channel
	// (u16), log time (u64) and size (u32), then its bytes; by the caller,
	// written from staged_at_ on; with a thread, what it has not yet taken
	// (under mu_).
	size_t staged_at_ = 0;
	std::mutex mu_;
	std::condition_variable cv_;
	std::vector<char> staged_;
	bool stop_ = false;
	std::thread thread_;
	Status status_ = Ok{}; // the first error (writing stops then)
};

} // namespace tcs
