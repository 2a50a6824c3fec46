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
// /tcs/record/journal (trace/record.h). Wall times count from the start of
// the run.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "error.h"
#include "mcap_writer.h"
#include "tcs/journal.h"

namespace tcs {

// How a trace is written: by a thread of its own, kept off the
// coordinator's core (avoid_cpu; -1: anywhere), where it takes what time the
// controllers leave; or by the coordinator itself (pumped), a message at a
// time in its idle moments (Trace::pump()), on a core of its own where a
// thread could only run while it sleeps (two cores: the controller's and
// the coordinator's, each spinning while the other works,
// docs/PERFORMANCE.md).
struct TraceWriting {
	bool pumped = false;
	int avoid_cpu = -1;
};

class Trace {
public:
	// Opens path. A record (--record) has the record's topics too.
	Status open(const std::string &path, TraceWriting how = TraceWriting{}, bool record = false);
	bool is_open() const { return open_; }
	Status close();
	// Pumped: writes the oldest message not yet written (false: none was
	// waiting). Some 1 us: the chunks are not compressed.
	bool pump();

	// Once per controller, before its first slice. name must outlive the
	// trace (the controller's does).
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
	// path must outlive the trace (a device's configured path does).
	void command(int controller, const std::string &path, int64_t v, std::vector<double> values, bool malformed);
	// The joint states each step records: their names, set once, then
	// their values, in that order, with each step.
	void set_joint_names(std::vector<std::string> names) { joint_names_ = std::move(names); }
	void step(int64_t v, int64_t wall_ns, int64_t wall_cost_ns, std::vector<double> joint_values);
	// A record (--record, trace/record.h): the run's settings a replay
	// needs, once, as JSON; and each controller's journal, in batches.
	void record_run(std::string json);
	void journal(int controller, std::vector<tcs_journal_entry> entries);

private:
	// What happened, as raw fields: formatting is the writer thread's work,
	// so that the run pays only for filling this in.
	struct Event {
		enum Kind : uint8_t { ControllerInfo, SliceEnd, Wait, Command, Step, RecordRun, Journal } kind;
		bool flag = false;          // wait: absolute; command: malformed
		int controller = 0;
		int64_t f[9] = {};          // the kind's numbers, in schema order
		double scale = 1;           // controller
		const char *text = "";      // why a slice ended; a wait's kind
		const std::string *path = nullptr; // command: the path; controller: the name
		std::vector<double> values; // command values; step joint values
		std::string json;           // the record's settings
		std::vector<tcs_journal_entry> entries; // a journal's batch
	};
	void emit(Event &&e);
	void write_oldest();
	void writer_loop(int avoid_cpu);
	void write_event(const Event &e); // in the writer thread

	// The writer thread's, once it runs, or the coordinator's. zstd level
	// 1: on a 1 kHz run's messages 7 % less work than level 3, and no
	// larger.
	std::optional<McapWriter> writer_;
	bool open_ = false;
	uint16_t controller_ = 0, slice_ = 0, wait_ = 0, device_ = 0, step_ = 0, clock_ = 0;
	uint16_t record_run_ = 0, journal_ = 0; // a record's
	std::vector<std::string> joint_names_;
	std::string buf_; // the message being written

	// Pumped: what is not yet written, all on the coordinator's thread.
	bool pumped_ = false;
	std::deque<Event> pending_;

	// With a thread: what it has not yet taken.
	std::mutex mu_;
	std::condition_variable cv_;
	std::vector<Event> queue_;
	bool stop_ = false;
	std::thread thread_;
	Status status_ = Ok{}; // the writer thread's first error (it stops writing then)
};

} // namespace tcs
