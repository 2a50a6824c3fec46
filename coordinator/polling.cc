// Polling: while a controller runs on a core of its own, the coordinator
// looks at the controllers' mailboxes (tcs/mailbox.h) between turns of its
// event loop instead of sleeping in epoll, for as long as requests keep
// coming (kPollFor after the last). A request then costs neither side a
// system call, where a hand-off through the channel costs two context
// switches or two inter-processor interrupts. It never polls while a
// controller runs on its own core, which polling from above (SCHED_FIFO)
// would hold off, nor in a run with remote peers, whose DDS threads share
// that core.
#include "polling.h"

#include "clock_ns.h"

namespace tcs {

bool MailboxPoller::take_all(const std::vector<std::unique_ptr<Controller>> &ctls)
{
	bool any = false;
	// Serving one may add controllers (a child): by index.
	for (size_t i = 0; i < ctls.size(); i++)
		any |= take_(*ctls[i]);
	return any;
}

bool MailboxPoller::worth_polling(const Lanes &lanes) const
{
	if (!enabled_ || !lanes.home().running.empty())
		return false;
	for (size_t i = 1; i < lanes.size(); i++)
		if (!lanes[i].running.empty())
			return true;
	return false;
}

void MailboxPoller::set_polling(const std::vector<std::unique_ptr<Controller>> &ctls, bool on)
{
	if (polling_ == on)
		return;
	polling_ = on;
	for (auto &c : ctls)
		c->mailbox.set_polling(on);
}

Status MailboxPoller::turn(EventLoop &loop, const Lanes &lanes, const std::vector<std::unique_ptr<Controller>> &ctls)
{
	if (worth_polling(lanes)) {
		const int64_t now = clock_ns(CLOCK_MONOTONIC);
		if (!polling_) {
			set_polling(ctls, true);
			polled_at_ = now;
		}
		if (take_all(ctls))
			polled_at_ = now;
		// Polling on while it has work of its own between looks: a sleep
		// would cost the next request a doorbell and a wake-up.
		if (now - polled_at_ < kPollFor || idle_work_) {
			auto n = loop.dispatch(0);
			if (!n)
				return n.error();
			if (*n > 0) {
				polled_at_ = now;
				return Ok{};
			}
			bool worked = idle_work_ && idle_work_();
			if (worked || now - polled_at_ < kPollFor)
				return Ok{};
		}
	}
	if (polling_) {
		// Unpromised first, then one more look: a request posted before
		// the promise was taken back is seen here, one after rings.
		set_polling(ctls, false);
		if (take_all(ctls))
			return Ok{};
	}
	// Its core is its own while no controller runs on it: work before
	// sleeping, looking for news after each piece.
	const bool own_core = enabled_ && lanes.home().running.empty();
	auto n = loop.dispatch(own_core && idle_work_ && idle_work_() ? 0 : -1);
	if (!n)
		return n.error();
	return Ok{};
}

} // namespace tcs
