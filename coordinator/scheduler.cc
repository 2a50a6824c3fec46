// The scheduling decision: see scheduler.h.
#include "scheduler.h"

#include <algorithm>

#include "tcs/vtime.h"

namespace tcs {

Decision decide(std::span<const Contender> cs, int64_t sim_ns, int64_t step_ns, bool barrier)
{
	const int64_t target = sim_ns + step_ns;
	Decision d;
	bool any = false, rechecks = false, running = false, best = false;
	int64_t next_event = TCS_NEVER;
	for (size_t i = 0; i < cs.size(); i++) {
		const Contender &c = cs[i];
		if (c.exited)
			continue;
		any = true;
		if (c.running) {
			running = true;
			continue;
		}
		rechecks |= c.rechecks;
		if (c.waits_on_running_child)
			continue; // (one is running: the decision waits at most)
		if (c.at < target && (!best || c.at < d.at)) {
			// The earliest behind the step; of equals, the first.
			best = true;
			d.who = i;
			d.at = c.at;
		} else if (c.at >= target) {
			next_event = std::min(next_event, c.at);
		}
	}
	if (!any)
		d.kind = Decision::Nobody;
	else if (best)
		d.kind = Decision::Run;
	else if (running)
		d.kind = Decision::Wait;
	else if (next_event == TCS_NEVER)
		d.kind = Decision::Idle;
	else {
		d.kind = Decision::Step;
		d.to = target;
		// Steps nobody acts in are skipped, to the one before the next
		// event (not with a re-check each step, nor at a barrier).
		if (!rechecks && !barrier && next_event > target)
			d.to = next_event - next_event % step_ns;
	}
	return d;
}

int64_t run_until(std::span<const Contender> cs, size_t who, int64_t target, int64_t duration_ns)
{
	int64_t horizon = TCS_NEVER;
	for (size_t i = 0; i < cs.size(); i++)
		if (i != who && !cs[i].exited)
			horizon = std::min(horizon, cs[i].rechecks ? target : cs[i].at);
	if (duration_ns >= 0)
		horizon = std::min(horizon, duration_ns);
	return std::max(target, horizon);
}

} // namespace tcs
