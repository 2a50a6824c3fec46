// The coordinator's one event loop: epoll over signalfd, pidfds, timerfds
// and controller channels, each with its handler. Nothing polls with sleeps.
#pragma once

#include <cstdint>
#include <functional>
#include <unordered_map>

#include "error.h"
#include "unique_fd.h"

namespace tcs {

class EventLoop {
public:
	using Handler = std::function<void(uint32_t events)>;

	Status init();
	Status add(int fd, Handler handler);
	void remove(int fd);
	// Waits for events (timeout_ms < 0: forever) and runs their handlers,
	// after on_wake if set; how many there were.
	Result<int> dispatch(int timeout_ms = -1);
	void set_on_wake(std::function<void()> f) { on_wake_ = std::move(f); }

private:
	std::function<void()> on_wake_;
	UniqueFd epoll_;
	std::unordered_map<int, Handler> handlers_;
};

// A CLOCK_MONOTONIC timerfd, armed relative to now.
class Timer {
public:
	Status init();
	void arm(int64_t ns, int64_t interval_ns = 0);
	void disarm() { arm(0); }
	// Consumes the expiration count; false if the timer had not fired.
	bool consume();
	int fd() const { return fd_.get(); }

private:
	UniqueFd fd_;
	// May have an expiry pending: disarming a timer that cannot costs no
	// system call (the scheduler disarms on every wait).
	bool armed_ = false;
	bool periodic_ = false;
};

} // namespace tcs
