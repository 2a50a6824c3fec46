// What coordinatord publishes over DDS for ROS 2 tools: the virtual clock
// on rt/clock and the joint states on rt/joint_states, one sample each per
// step of the world. The run's loop only copies a step's values into a
// ring; a thread of the bridge's own, off the controllers' core and at
// normal priority, does the DDS writes (some 20 us a step), so the world
// runs as fast with the bridge as without it.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "error.h"
#include "ros_publisher.h"
#include "sim_world.h"

namespace tcs {

class RosBridge {
public:
	// joints: "<model>.<joint>" names; their .position, .velocity and
	// .effort signals are published. Call before the coordinator takes
	// SCHED_FIFO and its core: DDS's threads and the bridge's inherit the
	// caller's policy and CPUs.
	static Result<std::unique_ptr<RosBridge>> start(uint32_t domain, std::vector<std::string> joints);
	~RosBridge() { stop(); }
	RosBridge(const RosBridge &) = delete;
	RosBridge &operator=(const RosBridge &) = delete;

	// From the run's loop after each step: never waits. A step that finds
	// the ring full is not published (counted).
	void step(int64_t sim_ns, const SimWorld &world);
	// Publishes what is queued, ends the thread, and says how many steps
	// were not published.
	uint64_t stop();

private:
	RosBridge() = default;
	void publish_loop();
	void publish(size_t slot);

	static constexpr size_t kRing = 4096;
	std::unique_ptr<RosPublisher> pub_;
	std::vector<std::string> joints_;
	// Signal indices per joint (-1: the world has none), found at the first step.
	std::vector<long> position_, velocity_, effort_;
	bool resolved_ = false;
	bool any_effort_ = false;
	// Single producer (the run's loop), single consumer (the thread).
	std::vector<int64_t> times_;
	std::vector<double> values_; // per slot: positions, velocities, efforts
	std::atomic<uint64_t> head_{ 0 }, tail_{ 0 };
	std::atomic<bool> stop_{ false };
	std::atomic<uint64_t> dropped_{ 0 };
	std::vector<double> scratch_;
	std::thread thread_;
};

} // namespace tcs
