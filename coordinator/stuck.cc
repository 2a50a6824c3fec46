// The watchdog on a controller that neither runs nor waits. A thread in a
// round trip counts each second of real time it has waited for its answer
// in the clock page (roundtrip.c). A wait is the coordinator's to end only
// while it holds the request; a thread still waiting when the coordinator
// holds none of its controller's, for seconds on end, will wait for ever:
// the request was lost on the way, or another's answer taken. That is a
// defect of tcs, never the program's, and the run would hang on it in
// silence; instead the controller is dropped, saying why (exit status 2).
// Counted in the controller and looked at from the progress timer, it costs
// the round trip nothing: the wait's ppoll carries a timeout instead of
// none.
#include "stuck.h"

#include <string>

#include "clock_ns.h"
#include "exits.h"
#include "threads.h"

namespace tcs {

namespace {
// How long the coordinator must hold nothing of a controller while a thread
// of it waits before it is taken for stuck: well past any hand-off.
constexpr int64_t kStuckAfter = 5 * TCS_NS_PER_S;
// A count this recent says a thread still waits (one a second per thread).
constexpr int64_t kStillWaiting = 2 * TCS_NS_PER_S + TCS_NS_PER_S / 2;
} // namespace

// Whether the coordinator holds a request of c's that it will answer, or
// has one of its unread: then whoever waits, waits for it.
static bool holds_request(const Controller &c)
{
	return c.wait.active || !c.side_waits.empty() || c.sync || c.wait.owed || c.woke_unheld ||
	       c.new_child.pid != 0 || request_unread(c);
}

void look_for_stuck(Run &run)
{
	if (run.ending)
		return;
	const int64_t now = clock_ns(CLOCK_MONOTONIC);
	for (auto &cp : run.ctls) {
		Controller &c = *cp;
		if (c.state() == CtlState::Exited || !c.dropped.empty())
			continue;
		Controller::StuckLook &s = c.stuck;
		const uint64_t n = c.unanswered_waits();
		if (n != s.unanswered)
			s.counted_at = now;
		s.unanswered = n;
		// (The count first: holding a request is asked of the channels.)
		if (now - s.counted_at > kStillWaiting || holds_request(c)) {
			s.since = 0;
			continue;
		}
		if (s.since == 0) {
			s.since = now;
			continue;
		}
		if (now - s.since >= kStuckAfter)
			drop(run, c,
			     "it is stuck: a thread of it has waited more than " + std::to_string(kStuckAfter / TCS_NS_PER_S) +
				     " s for the answer to a request tcs does not hold (a defect of tcs: please report it, "
				     "with the command line)");
	}
}

} // namespace tcs
