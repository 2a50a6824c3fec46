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
	using Take = std::function<bool(Controller &)>;
	// Mailboxes are used at all (the machine allows, and no remote peers);
	// take serves c's posted request (false: none).
	void enable(bool on, Take take)
	{
		enabled_ = on;
		take_ = std::move(take);
	}
	bool enabled() const { return enabled_; }
	// Work for the coordinator's idle moments on its own core (writing the
	// trace's messages into its file): one piece of it, false when there
	// is none. Done between looks while polling, and before sleeping while
	// no controller runs on that core.
	using Work = std::function<bool()>;
	void set_idle_work(Work work) { idle_work_ = std::move(work); }
	// One turn of the run's loop: the mailboxes polled and the loop's
	// ready fds served without sleeping, while worth it; else a sleep in
	// epoll.
	Status turn(EventLoop &loop, const Lanes &lanes, const std::vector<std::unique_ptr<Controller>> &ctls);

private:
	bool worth_polling(const Lanes &lanes) const;
	void set_polling(const std::vector<std::unique_ptr<Controller>> &ctls, bool on);
	bool take_all(const std::vector<std::unique_ptr<Controller>> &ctls);
	Take take_;
	Work idle_work_;
	bool enabled_ = false;
	bool polling_ = false;
	int64_t polled_at_ = 0; // wall ns of the last request or event while polling
};

} // namespace tcs
