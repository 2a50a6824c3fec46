// Lanes: controllers run in parallel, one on each core tcs may use (its
// affinity mask when it started; docs/DESIGN.md §2). Conservative
// synchronisation already lets every controller behind the world's next
// step run in any order: each has its own virtual CPU, and nothing it sees
// of the world or of another controller changes before the step. So each
// core is a lane with its own running controller, budget timer and
// watchdog. The coordinator's core is lane 0 and preferred: there a
// hand-off is a same-core switch, where another core's costs an
// inter-processor interrupt (15 against 26 us on one VM). A controller is
// pinned to its lane's core before it resumes, all its threads (children
// are controllers of their own).
//
// In lockstep beside a polling coordinator (mailboxes), a lane may hold
// several: every controller behind the step is resumed at once, queued on
// the other cores, and the kernel runs them one after another (SCHED_FIFO:
// each holds its core until it waits). Computation is free there, so the
// order changes no virtual time, and a controller going from one to the
// next costs one context switch on its core, where handing the core over
// through the coordinator costs it a round of the coordinator's as well
// (45 against 28 us a controller-cycle, sixteen pendulums on one VM). A
// queued controller parks its requests at once (TCS_PAGE_QUEUED): the one
// behind it has the core meanwhile.
#include "lanes.h"

#include <algorithm>

#include "clock_ns.h"
#include "realtime.h"

namespace tcs {

Status Lanes::init(const Setup &setup, EventLoop &loop, std::function<void(Lane &)> on_budget,
		   std::function<void(Lane &)> on_watchdog)
{
	setup_ = setup;
	std::vector<int> cores = setup.cores;
	if (cores.empty())
		cores.push_back(-1); // not pinned: one lane, wherever the kernel puts it
	for (int cpu : cores) {
		auto lane = std::make_unique<Lane>();
		lane->cpu = cpu;
		lane->stop_cost = lanes_.empty() ? setup.stop_home : setup.stop_other;
		for (Timer *t : { &lane->budget, &lane->watchdog })
			if (auto s = t->init(); !s)
				return s;
		Lane *raw = lane.get();
		if (auto s = loop.add(raw->budget.fd(), [on_budget, raw](uint32_t) { on_budget(*raw); }); !s)
			return s;
		if (auto s = loop.add(raw->watchdog.fd(), [on_watchdog, raw](uint32_t) { on_watchdog(*raw); }); !s)
			return s;
		lanes_.push_back(std::move(lane));
	}
	return Ok{};
}

// The lane other than the coordinator's with the fewest queued, the one of
// the core c was on if it is among them (no move); -1 if there is none.
int Lanes::shortest_other(const Controller &c) const
{
	int best = -1;
	for (size_t i = 1; i < lanes_.size(); i++) {
		const size_t n = lanes_[i]->running.size();
		if (best < 0 || n < lanes_[(size_t)best]->running.size() ||
		    (n == lanes_[(size_t)best]->running.size() && lanes_[i]->cpu == c.core))
			best = (int)i;
	}
	return best;
}

// A free lane other than the coordinator's, the one of the core c was on
// first (no move); -1 if none.
int Lanes::free_other(const Controller &c) const
{
	const int best = shortest_other(c);
	return best >= 0 && lanes_[(size_t)best]->running.empty() ? best : -1;
}

// With mailboxes, another core is where a controller's hand-offs are
// cheapest (the coordinator polls for them from its own), and a controller
// on the coordinator's core stops that polling. So: another free core; the
// coordinator's core only for one that computes long enough between
// requests for the channel's hand-off not to matter (then two run at
// once); else, in lockstep, queued on another core, else wait for one.
//
// Without: the coordinator's core if free, else another. A controller that
// holds a core only briefly (a lockstep loop that reads, writes and sleeps)
// waits for the coordinator's core while the one there is as brief:
// another core's hand-off costs an inter-processor interrupt each way,
// more than such a turn of the coordinator's core takes. (One there that
// turns out long is seen by its lane's watchdog, which schedules again:
// asleep.cc.)
int Lanes::free_for(const Controller &c) const
{
	const Lane &home = *lanes_.front();
	if (setup_.mailboxes) {
		int other = free_other(c);
		if (other >= 0)
			return other;
		if (home.running.empty() && c.turn_cpu >= kWorthAnotherCore)
			return 0;
		return setup_.lockstep ? shortest_other(c) : -1;
	}
	if (home.running.empty())
		return 0;
	const Controller &there = *home.running.front();
	if (c.turn_cpu < kWorthAnotherCore && there.turn_cpu < kWorthAnotherCore &&
	    clock_ns(CLOCK_MONOTONIC) - there.resumed_wall < kWorthAnotherCore)
		return -1;
	return free_other(c);
}

void Lanes::take(Controller &c, int index)
{
	Lane &lane = *lanes_[(size_t)index];
	if (lane.cpu >= 0 && c.core != lane.cpu) {
		// Its threads, stopped or waiting: none is running meanwhile.
		pin_threads(c.multithreaded() ? threads_of(c.pid) : std::vector<pid_t>{ c.pid }, lane.cpu);
		c.core = lane.cpu;
		c.set_page_flag(TCS_PAGE_SHARES_CORE, lane.cpu == setup_.coordinator_cpu);
		c.set_page_flag(TCS_PAGE_MAILBOX, setup_.mailboxes && lane.cpu != setup_.coordinator_cpu);
	}
	lane.running.push_back(&c);
	set_queued(lane);
	// What it computes in a turn (from one resume to the next): the less
	// of its last two, for in lockstep the charges are mostly learnt and
	// a turn now and then takes up what the others missed (cpu_estimate.c:
	// 500 us at once, seen), which must not make a light one look heavy.
	const int64_t turn = (int64_t)((double)(c.charged - c.charged_at_turn) / c.scale);
	c.turn_cpu = std::min(turn, c.last_turn_cpu);
	c.last_turn_cpu = turn;
	c.charged_at_turn = c.charged;
	c.lane = index;
	c.slices++;
}

Lane *Lanes::of(const Controller &c)
{
	return c.lane >= 0 && (size_t)c.lane < lanes_.size() ? lanes_[(size_t)c.lane].get() : nullptr;
}

void Lanes::leave(Controller &c)
{
	Lane *lane = of(c);
	if (!lane)
		return;
	lane->budget.disarm(); // (its watchdog ticks on: asleep.cc)
	std::erase(lane->running, &c);
	c.set_page_flag(TCS_PAGE_QUEUED, false);
	set_queued(*lane);
	c.lane = -1;
}

// Tells those in the lane whether others are queued with them.
void Lanes::set_queued(Lane &lane)
{
	const bool queued = lane.running.size() > 1;
	for (Controller *c : lane.running)
		c->set_page_flag(TCS_PAGE_QUEUED, queued);
}

bool Lanes::any_running() const
{
	return std::any_of(lanes_.begin(), lanes_.end(), [](auto &l) { return !l->running.empty(); });
}

} // namespace tcs
