// Polling: while a controller runs on a core of its own, the coordinator
// looks at the controllers' mailboxes (tcs/mailbox.h) between turns of its
// event loop instead of sleeping in epoll, for as long as requests keep
// coming (kPollFor after the last). A request then costs neither side a
// system call, where a hand-off through the channel costs two context
// switches or two inter-processor interrupts. It never polls while a
// controller runs on its own core, which polling from above (SCHED_FIFO)
// would hold off, nor in a run with remote peers, whose DDS threads share
// that core.
#include "coordinator.h"

namespace tcs {

bool Coordinator::take_mailbox(Controller &c)
{
	alignas(8) unsigned char buf[sizeof(struct tcs_msg)];
	if (!c.mailbox.take(buf))
		return false;
	struct tcs_msg m;
	const char *why = tcs_msg_check(buf, sizeof buf, &m);
	if (!why && !tcs_mailbox_carries(m.type))
		why = "a request the mailbox does not carry";
	if (why) {
		devices_.take_lazy_commands(c, -1, trace_);
		drop(c, std::string("bad request in its mailbox: ") + why);
		return true;
	}
	on_request(c, nullptr, m, UniqueFd{});
	// Not answered at once: it waits on its channel, off its core, which
	// the coordinator may give to another controller meanwhile.
	c.mailbox.park();
	return true;
}

bool Coordinator::take_mailboxes()
{
	bool any = false;
	// Serving one may add controllers (a child): by index.
	for (size_t i = 0; i < ctls_.size(); i++)
		any |= take_mailbox(*ctls_[i]);
	return any;
}

bool Coordinator::worth_polling() const
{
	if (!mailboxes_ || !lanes_.home().running.empty())
		return false;
	for (size_t i = 1; i < lanes_.size(); i++)
		if (!lanes_[i].running.empty())
			return true;
	return false;
}

void Coordinator::set_polling(bool on)
{
	if (polling_ == on)
		return;
	polling_ = on;
	for (auto &c : ctls_)
		c->mailbox.set_polling(on);
}

Status Coordinator::turn()
{
	if (worth_polling()) {
		const int64_t now = wall_now();
		if (!polling_) {
			set_polling(true);
			polled_at_ = now;
		}
		if (take_mailboxes())
			polled_at_ = now;
		if (now - polled_at_ < kPollFor) {
			auto n = loop_.dispatch(0);
			if (!n)
				return n.error();
			if (*n > 0)
				polled_at_ = now;
			return Ok{};
		}
	}
	if (polling_) {
		// Unpromised first, then one more look: a request posted before
		// the promise was taken back is seen here, one after rings.
		set_polling(false);
		if (take_mailboxes())
			return Ok{};
	}
	auto n = loop_.dispatch(-1);
	if (!n)
		return n.error();
	return Ok{};
}

} // namespace tcs
