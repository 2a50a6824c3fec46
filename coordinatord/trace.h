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
	void command(int controller, const std::string &path, int64_t v, const std::vector<double> &values,
		     bool malformed);
	// joints: (name, value) of every scalar position/velocity signal.
	void step(int64_t v, int64_t wall_cost_ns, const std::vector<std::pair<std::string, double>> &joints);

private:
	struct Pending {
		uint16_t channel;
		uint64_t time;
		std::string json;
	};
	void emit(uint16_t channel, int64_t v);
	void writer_loop(int avoid_cpu);

	McapWriter writer_; // the writer thread's, once it runs
	bool open_ = false;
	uint16_t slice_ = 0, wait_ = 0, device_ = 0, step_ = 0, clock_ = 0;
	std::string json_; // the message being formatted

	std::mutex mu_;
	std::condition_variable cv_;
	std::vector<Pending> queue_; // formatted, not yet written
	bool stop_ = false;
	std::thread thread_;
	Status status_ = Ok{}; // the writer thread's first error (it stops writing then)
};

} // namespace tcs
