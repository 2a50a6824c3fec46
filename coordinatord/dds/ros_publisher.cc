// RosPublisher: the Cyclone DDS entities, their QoS, and the samples built
// without allocating from the values the coordinator passes in.
#include "ros_publisher.h"

#include <type_traits>

#include <dds/dds.h>

#include "ros_clock.h"
#include "ros_joint_state.h"

namespace tcs {

static_assert(std::is_same_v<dds_entity_t, int32_t>, "ros_publisher.h keeps DDS entities as int32_t");

namespace {

// A reliable writer blocks in dds_write when its unacknowledged data passes
// Cyclone's high-water mark (a reader too slow to acknowledge). The caller
// is the real-time coordinator loop, so it never waits: such a sample is
// dropped and counted, the right loss for telemetry of a moving state.
constexpr dds_duration_t max_blocking_time = 0;

Error dds_error(const std::string &what, dds_return_t rc)
{
	return Error{ "DDS: " + what + ": " + dds_strretcode(rc) };
}

// rmw_cyclonedds reads XCDR1 only, and a writer serialises in the first
// representation its QoS lists: say XCDR1 rather than rely on a default.
dds_qos_t *ros_qos(int32_t depth)
{
	dds_qos_t *q = dds_create_qos();
	dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, max_blocking_time);
	dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
	dds_qset_history(q, DDS_HISTORY_KEEP_LAST, depth);
	const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
	dds_qset_data_representation(q, 1, &xcdr1);
	return q;
}

Result<dds_entity_t> make_writer(dds_entity_t participant, const dds_topic_descriptor_t *type, const char *topic_name,
				 int32_t depth)
{
	dds_entity_t topic = dds_create_topic(participant, type, topic_name, nullptr, nullptr);
	if (topic < 0)
		return dds_error(std::string("creating topic ") + topic_name, topic);
	dds_qos_t *q = ros_qos(depth);
	dds_entity_t w = dds_create_writer(participant, topic, q, nullptr);
	dds_delete_qos(q);
	if (w < 0)
		return dds_error(std::string("creating the writer of ") + topic_name, w);
	return w;
}

// ROS time is a signed second count and the nanoseconds past it; floor
// division keeps nanosec in [0, 1e9) for times before the epoch too. The
// int32 seconds last 68 years of virtual time.
builtin_interfaces_msg_dds__Time_ ros_time(int64_t ns)
{
	int64_t sec = ns / 1000000000;
	int64_t rem = ns % 1000000000;
	if (rem < 0) {
		sec--;
		rem += 1000000000;
	}
	return { static_cast<int32_t>(sec), static_cast<uint32_t>(rem) };
}

// A sequence that lends the caller's array to dds_write, which only reads
// it and has serialised it when it returns: no copy, no allocation.
dds_sequence_double lent(const double *values, uint32_t n)
{
	if (!values)
		return { 0, 0, nullptr, false };
	return { n, n, const_cast<double *>(values), false };
}

} // namespace

Result<std::unique_ptr<RosPublisher>> RosPublisher::create(uint32_t domain, std::vector<std::string> joint_names)
{
	std::unique_ptr<RosPublisher> p(new RosPublisher());
	p->participant_ = dds_create_participant(domain, nullptr, nullptr);
	if (p->participant_ < 0) {
		dds_return_t rc = p->participant_;
		p->participant_ = 0;
		return dds_error("creating the participant in domain " + std::to_string(domain), rc);
	}
	// rclcpp's ClockQoS (what every node's use_sim_time clock subscribes
	// with) is best effort, keep last 1. A reliable writer serves
	// best-effort and reliable readers alike, where a best-effort one would
	// leave unmatched any reader asking for reliable (rclcpp's default QoS);
	// keep last 1 because only the newest time matters.
	auto clock = make_writer(p->participant_, &rosgraph_msgs_msg_dds__Clock__desc, "rt/clock", 1);
	if (!clock)
		return clock.error();
	p->clock_writer_ = *clock;
	// ROS 2's default QoS, what robot_state_publisher subscribes with.
	auto joints = make_writer(p->participant_, &sensor_msgs_msg_dds__JointState__desc, "rt/joint_states", 10);
	if (!joints)
		return joints.error();
	p->joints_writer_ = *joints;
	p->names_ = std::move(joint_names);
	for (auto &n : p->names_)
		p->name_ptrs_.push_back(n.data());
	return p;
}

RosPublisher::~RosPublisher()
{
	// Deleting a writer lingers (up to a second) until reliable readers
	// have acknowledged what it wrote, so the last samples get through.
	if (participant_ > 0)
		dds_delete(participant_);
}

void RosPublisher::clock(int64_t sim_ns)
{
	rosgraph_msgs_msg_dds__Clock_ sample{ ros_time(sim_ns) };
	if (dds_write(clock_writer_, &sample) < 0)
		dropped_++;
}

void RosPublisher::joint_states(int64_t sim_ns, const double *position, const double *velocity, const double *effort)
{
	static char no_frame[] = "";
	const auto n = static_cast<uint32_t>(names_.size());
	sensor_msgs_msg_dds__JointState_ sample{};
	sample.header.stamp = ros_time(sim_ns);
	sample.header.frame_id = no_frame;
	sample.name = { n, n, name_ptrs_.data(), false };
	sample.position = lent(position, n);
	sample.velocity = lent(velocity, n);
	sample.effort = lent(effort, n);
	if (dds_write(joints_writer_, &sample) < 0)
		dropped_++;
}

} // namespace tcs
