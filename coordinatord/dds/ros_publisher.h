// The virtual clock and joint states as ROS 2 topics (rt/clock,
// rt/joint_states) on Cyclone DDS, so stock ROS 2 tools follow virtual time.
//
// Cyclone starts its threads (receive, timed events, garbage collection)
// when create() makes the participant. The coordinator therefore creates
// the publisher before it switches itself to SCHED_FIFO and pins itself to
// a core: those threads inherit the ordinary policy and stay off the core.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "error.h"

namespace tcs {

class RosPublisher {
public:
	// domain: DDS domain id. Creates the participant, the topics rt/clock
	// and rt/joint_states and a writer for each.
	static Result<std::unique_ptr<RosPublisher>> create(uint32_t domain, std::vector<std::string> joint_names);
	~RosPublisher(); // deletes the participant, and with it all the rest
	RosPublisher(const RosPublisher &) = delete;
	RosPublisher &operator=(const RosPublisher &) = delete;

	// Both writes run on the caller's thread: serialise, then sendto (some
	// 10 us each on loopback). They never wait for a reader (see
	// max_blocking_time in the .cc); tcs allocates nothing per call, though
	// Cyclone itself allocates the serialised sample.

	// One rosgraph_msgs Clock_ sample: the sec/nanosec of sim_ns.
	void clock(int64_t sim_ns);
	// One JointState_ sample stamped sim_ns, with the names given to
	// create() and the values as given, each array as long as the names.
	// An array may be null (effort usually is): it is then sent empty, as
	// ROS allows.
	void joint_states(int64_t sim_ns, const double *position, const double *velocity, const double *effort);

	// Samples not sent because the writer would have had to block (a
	// reliable reader too slow to acknowledge) or failed otherwise.
	uint64_t dropped() const { return dropped_; }

private:
	RosPublisher() = default;
	// dds_entity_t, kept out of this header (the .cc checks the type).
	int32_t participant_ = 0;
	int32_t clock_writer_ = 0;
	int32_t joints_writer_ = 0;
	std::vector<std::string> names_;
	// The sample's name sequence points here, made once at create().
	std::vector<char *> name_ptrs_;
	uint64_t dropped_ = 0;
};

} // namespace tcs
