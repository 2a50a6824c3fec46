// RosBridge: a ring of steps from the run's loop to a publishing thread.
#include "ros_bridge.h"

#include <time.h>

#include <cmath>

namespace tcs {

Result<std::unique_ptr<RosBridge>> RosBridge::start(uint32_t domain, std::vector<std::string> joints)
{
	auto pub = RosPublisher::create(domain, joints);
	if (!pub)
		return Error{ "DDS domain " + std::to_string(domain) + ": " + pub.error().message };
	std::unique_ptr<RosBridge> b(new RosBridge());
	b->pub_ = std::move(*pub);
	b->joints_ = std::move(joints);
	b->times_.resize(kRing);
	b->values_.resize(kRing * 3 * b->joints_.size());
	b->thread_ = std::thread([raw = b.get()] { raw->publish_loop(); });
	return b;
}

uint64_t RosBridge::stop()
{
	stop_.store(true, std::memory_order_release);
	if (thread_.joinable())
		thread_.join();
	return dropped_.load(std::memory_order_relaxed) + pub_->dropped();
}

void RosBridge::step(int64_t sim_ns, const SimWorld &world)
{
	const size_t n = joints_.size();
	if (!resolved_) {
		for (const auto &j : joints_) {
			position_.push_back(world.find(j + ".position"));
			velocity_.push_back(world.find(j + ".velocity"));
			effort_.push_back(world.find(j + ".effort"));
			any_effort_ |= effort_.back() >= 0;
		}
		resolved_ = true;
	}
	uint64_t head = head_.load(std::memory_order_relaxed);
	if (head - tail_.load(std::memory_order_acquire) >= kRing) {
		dropped_.fetch_add(1, std::memory_order_relaxed);
		return;
	}
	size_t slot = head % kRing;
	times_[slot] = sim_ns;
	double *v = &values_[slot * 3 * n];
	auto put = [&](const std::vector<long> &index, double *out) {
		for (size_t i = 0; i < n; i++) {
			scratch_.clear();
			if (index[i] >= 0)
				world.read((size_t)index[i], scratch_);
			out[i] = scratch_.empty() ? NAN : scratch_[0];
		}
	};
	put(position_, v);
	put(velocity_, v + n);
	put(effort_, v + 2 * n);
	head_.store(head + 1, std::memory_order_release);
}

void RosBridge::publish(size_t slot)
{
	const size_t n = joints_.size();
	const double *v = &values_[slot * 3 * n];
	pub_->clock(times_[slot]);
	if (n > 0)
		pub_->joint_states(times_[slot], v, v + n, any_effort_ ? v + 2 * n : nullptr);
}

// Polls the ring every 200 us: the run's loop then never makes a system
// call to wake it, and ROS tools see a step at most that much later.
void RosBridge::publish_loop()
{
	for (;;) {
		bool stopping = stop_.load(std::memory_order_acquire);
		uint64_t head = head_.load(std::memory_order_acquire);
		uint64_t tail = tail_.load(std::memory_order_relaxed);
		for (; tail != head; tail++) {
			publish(tail % kRing);
			tail_.store(tail + 1, std::memory_order_release);
		}
		if (stopping)
			return;
		struct timespec pause = { 0, 200000 };
		nanosleep(&pause, nullptr);
	}
}

} // namespace tcs
