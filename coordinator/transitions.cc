// A controller's moves between states (transitions.h).
#include "transitions.h"

#include <unistd.h>

#include <algorithm>

namespace tcs {

bool move(Run &run, Controller &c, CtlMove m)
{
	if (const auto to = after(c.state(), m)) {
		c.state_ = *to;
		// Waiting again, or running without an answer: none is owed.
		if (m == CtlMove::Block || m == CtlMove::SetAside || m == CtlMove::StepAside || m == CtlMove::Awake ||
		    m == CtlMove::Drop)
			c.wait.owed = false;
		return true;
	}
	warn_once(run, "controller " + c.name + ": '" + move_name(m) + "' while " + state_name(c.state()) +
			       " is not a move it can make (a defect of tcs: please report it)");
	return false;
}

void advance(Controller &c, int64_t at)
{
	c.v_ = std::max(c.v_, at);
}

void place_at(Controller &c, int64_t at)
{
	c.v_ = at;
}

void serve_request(Controller &c, uint32_t seq, int fd)
{
	c.wait.seq = seq;
	c.wait.fd = fd;
}

void block(Run &run, Controller &c, const WaitEnds &ends, CtlMove how)
{
	if (!move(run, c, how))
		return;
	c.wait.deadline = ends.deadline;
	c.wait.recheck = ends.recheck;
	c.wait.devices = ends.devices;
	c.wait.for_child = ends.for_child;
	c.wait.rechecked_at = run.sim_ns;
	c.wait.signalled_at = TCS_NEVER;
	c.wait.active = false;
}

void block_in(Run &run, Controller &c, const Request &r, const WaitEnds &ends)
{
	block(run, c, ends);
	static_cast<Request &>(c.wait) = r;
	c.wait.active = true;
}

void awake(Run &run, Controller &c)
{
	if (move(run, c, CtlMove::Awake))
		c.wait.recheck = false;
}

void looked_at(Run &run, Controller &c, bool signal_too)
{
	c.wait.rechecked_at = run.sim_ns;
	if (signal_too)
		forget_signal(c);
}

void forget_signal(Controller &c)
{
	c.wait.signalled_at = TCS_NEVER;
}

void own_wait_beside(Run &, Controller &c)
{
	if (c.wait.active) {
		c.side_waits.push_back(c.own_wait());
		c.wait.active = false;
		c.wait.owed = false;
	}
	c.wait.deadline = TCS_NEVER;
	c.wait.recheck = false;
	c.wait.devices = false;
	c.wait.for_child = false;
}

void own_wait_from(Controller &c, const Request &w)
{
	static_cast<Request &>(c.wait) = w;
	c.wait.active = true;
}

bool set_own_wait_aside(Run &run, Controller &c, int fd)
{
	if (!c.wait.active || fd == (c.wait.fd >= 0 ? c.wait.fd : c.channel.get()))
		return false;
	own_wait_beside(run, c);
	if (c.state() == CtlState::Blocked)
		move(run, c, CtlMove::SetAside);
	return true;
}

void answered(Controller &c)
{
	if (c.wait.pass_fd >= 0) {
		close(c.wait.pass_fd);
		c.wait.pass_fd = -1;
	}
	c.wait.active = false;
	c.wait.result = 0;
	c.wait.owed = false;
}

void owe_answer(Controller &c, uint16_t reason, int64_t result)
{
	c.wait.owed = true;
	c.wait.reason = reason;
	c.wait.result = result;
}

void wake(Run &run, Controller &c, int64_t v, uint16_t reason, int64_t result)
{
	advance(c, v);
	move(run, c, CtlMove::Wake);
	c.wait.recheck = false;
	c.wait.signalled_at = TCS_NEVER;
	c.wait.devices = false;
	owe_answer(c, reason, result);
}

} // namespace tcs
