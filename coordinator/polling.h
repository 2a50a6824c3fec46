// Polling the controllers' mailboxes between turns of the run's event loop
// instead of sleeping in epoll, while it is worth it (polling.cc says when).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "controller.h"
#include "error.h"
#include "event_loop.h"
#include "lanes.h"

namespace tcs {

class MailboxPoller {
public:
	// How long it polls after the last request or event.
	static constexpr int64_t kPollFor = 30 * TCS_NS_PER_US;
	// Mailboxes are used at all (the machine allows, and no remote peers).
	void enable(bool on) { enabled_ = on; }
	bool enabled() const { return enabled_; }
	// One turn of the run's loop: the mailboxes polled (take: c's posted
	// request served, false if none) and the loop's ready fds served
	// without sleeping, while worth it; else a sleep in epoll.
	Status turn(EventLoop &loop, const Lanes &lanes, const std::vector<std::unique_ptr<Controller>> &ctls,
		    const std::function<bool(Controller &)> &take);

private:
	bool worth_polling(const Lanes &lanes) const;
	void set_polling(const std::vector<std::unique_ptr<Controller>> &ctls, bool on);
	static bool take_all(const std::vector<std::unique_ptr<Controller>> &ctls,
			     const std::function<bool(Controller &)> &take);
	bool enabled_ = false;
	bool polling_ = false;
	int64_t polled_at_ = 0; // wall ns of the last request or event while polling
};

} // namespace tcs
