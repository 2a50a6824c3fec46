// The run's trace (DESIGN.md §6): an MCAP file of JSON messages with JSON
// Schemas, which Foxglove and PlotJuggler decode, logged at virtual time.
// Topics: /tcs/slice (each stretch a controller ran: virtual and wall start
// and end, CPU charged, why it ended), /tcs/wait (each hooked wait: kind,
// requested deadline, when it ended), /tcs/device (each command written to
// an actuator), /tcs/step (each simulation step's wall cost and joint
// states) and /clock (the simulation clock, as ROS 2 publishes it).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "error.h"
#include "mcap_writer.h"

namespace tcs {

class Trace {
public:
	// Opens path; the file is written by a thread of its own kept off core
	// avoid_cpu (the controllers' core; -1: anywhere), so that compression
	// and writing do not take time from the run.
	Status open(const std::string &path, int avoid_cpu = -1);
	bool is_open() const { return open_; }
	Status close();

	void slice(int controller, int64_t v_start, int64_t v_end, int64_t charged_ns, int64_t wall_start,
		   int64_t wall_end, const char *why);
	void wait(int controller, const char *kind, int64_t v_request, int64_t deadline, int64_t v_end, bool absolute);
	// path must outlive the trace (a device's configured path does).
	void command(int controller, const std::string &path, int64_t v, std::vector<double> values, bool malformed);
	// The joint states each step records: their names, set once, then
	// their values, in that order, with each step.
	void set_joint_names(std::vector<std::string> names) { joint_names_ = std::move(names); }
	void step(int64_t v, int64_t wall_cost_ns, std::vector<double> joint_values);

private:
	// What happened, as raw fields: formatting is the writer thread's work,
	// so that the run pays only for filling this in.
	struct Event {
		enum Kind : uint8_t { Slice, Wait, Command, Step } kind;
		bool flag = false;          // wait: absolute; command: malformed
		int controller = 0;
		int64_t f[6] = {};          // the kind's numbers, in schema order
		const char *text = "";      // why a slice ended; a wait's kind
		const std::string *path = nullptr; // command
		std::vector<double> values; // command values; step joint values
	};
	void emit(Event &&e);
	void writer_loop(int avoid_cpu);
	void write_event(const Event &e); // in the writer thread

	McapWriter writer_; // the writer thread's, once it runs
	bool open_ = false;
	uint16_t slice_ = 0, wait_ = 0, device_ = 0, step_ = 0, clock_ = 0;
	std::vector<std::string> joint_names_;
	std::string json_; // the writer thread's formatting buffer

	std::mutex mu_;
	std::condition_variable cv_;
	std::vector<Event> queue_; // not yet written
	bool stop_ = false;
	std::thread thread_;
	Status status_ = Ok{}; // the writer thread's first error (it stops writing then)
};

} // namespace tcs
