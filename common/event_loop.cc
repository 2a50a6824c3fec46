// EventLoop and Timer: thin wrappers over epoll and timerfd.
#include "event_loop.h"

#include <sys/epoll.h>
#include <sys/timerfd.h>

#include "tcs/vtime.h"

namespace tcs {

Status EventLoop::init()
{
	epoll_.reset(epoll_create1(EPOLL_CLOEXEC));
	if (!epoll_)
		return errno_error("epoll_create1");
	return Ok{};
}

Status EventLoop::add(int fd, Handler handler)
{
	struct epoll_event ev = {};
	ev.events = EPOLLIN;
	ev.data.fd = fd;
	if (epoll_ctl(epoll_.get(), EPOLL_CTL_ADD, fd, &ev) < 0)
		return errno_error("epoll_ctl");
	handlers_[fd] = std::move(handler);
	return Ok{};
}

void EventLoop::remove(int fd)
{
	epoll_ctl(epoll_.get(), EPOLL_CTL_DEL, fd, nullptr);
	handlers_.erase(fd);
}

Result<int> EventLoop::dispatch(int timeout_ms)
{
	struct epoll_event evs[16];
	int n = epoll_wait(epoll_.get(), evs, 16, timeout_ms);
	if (n < 0) {
		if (errno == EINTR)
			return 0;
		return errno_error("epoll_wait");
	}
	if (n == 0)
		return 0;
	if (on_wake_)
		on_wake_();
	for (int i = 0; i < n; i++) {
		// A handler may have removed a later fd of this batch: look it up now.
		auto it = handlers_.find(evs[i].data.fd);
		if (it != handlers_.end()) {
			Handler h = it->second;
			h(evs[i].events);
		}
	}
	return n;
}

Status Timer::init()
{
	fd_.reset(timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK));
	if (!fd_)
		return errno_error("timerfd_create");
	return Ok{};
}

void Timer::arm(int64_t ns, int64_t interval_ns)
{
	if (ns <= 0 && !armed_)
		return;
	armed_ = ns > 0;
	periodic_ = interval_ns > 0;
	struct itimerspec its = {};
	its.it_value = tcs_ns_to_ts(ns);
	its.it_interval = tcs_ns_to_ts(interval_ns);
	timerfd_settime(fd_.get(), 0, &its, nullptr);
}

bool Timer::consume()
{
	uint64_t n;
	bool fired = read(fd_.get(), &n, sizeof n) == (ssize_t)sizeof n;
	if (fired && !periodic_)
		armed_ = false;
	return fired;
}

} // namespace tcs
