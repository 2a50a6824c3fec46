// Lanes: controllers run in parallel, one on each core tcs may use (a lane
// per core, with its running controllers, budget timer and watchdog); the
// choice of a lane for a controller about to run, and moving it there.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "controller.h"
#include "error.h"
#include "event_loop.h"
#include "stop_cost.h"
#include "tcs/protocol.h"

namespace tcs {

struct Lane {
	int cpu = -1; // its core (-1: not pinned)
	std::vector<Controller *> running; // in the order they were resumed
	Timer budget;   // the running controller's budget (cpu mode)
	Timer watchdog; // looks at them if they may be asleep (asleep.cc)
	bool watching = false; // the watchdog ticks
	StopCost stop_cost;    // what a stop from here costs a controller here
};

class Lanes {
public:
	// A turn on a core shorter than this is not worth another core's
	// hand-off: a few inter-processor interrupts on a VM.
	static constexpr int64_t kWorthAnotherCore = 50 * TCS_NS_PER_US;

	struct Setup {
		std::vector<int> cores; // tcs may use (empty: one lane, not pinned)
		int coordinator_cpu = -1; // the coordinator's own core (lane 0's)
		bool mailboxes = false;   // controllers post requests, the coordinator polls
		bool lockstep = false;
		// What a stop costs a controller on the coordinator's core, and
		// on another (stop_cost.h).
		StopCost stop_home, stop_other;
	};
	// The lanes' timers are on loop, calling on_budget and on_watchdog.
	Status init(const Setup &setup, EventLoop &loop, std::function<void(Lane &)> on_budget,
		    std::function<void(Lane &)> on_watchdog);

	// The lane c would run in now; -1 if it had better wait.
	int free_for(const Controller &c) const;
	// c runs in lane index from now: pinned to its core, its turn counted.
	void take(Controller &c, int index);
	// c no longer runs in its lane (it waits, was stopped, ended): the
	// lane's budget timer is off and another may take it.
	void leave(Controller &c);
	Lane *of(const Controller &c);
	bool any_running() const;
	// The coordinator's core's, first: its controller's estimates go stale
	// whenever the coordinator runs.
	Lane &home() { return *lanes_.front(); }
	const Lane &home() const { return *lanes_.front(); }
	bool is_home(const Lane &l) const { return &l == lanes_.front().get(); }
	size_t size() const { return lanes_.size(); }
	Lane &operator[](size_t i) { return *lanes_[i]; }
	const Lane &operator[](size_t i) const { return *lanes_[i]; }
	void disarm_budgets()
	{
		for (auto &l : lanes_)
			l->budget.disarm();
	}
	template <class F> void each_running(F f)
	{
		for (auto &l : lanes_)
			for (Controller *c : l->running)
				f(*c);
	}

private:
	int shortest_other(const Controller &c) const;
	int free_other(const Controller &c) const;
	void set_queued(Lane &lane);

	Setup setup_;
	std::vector<std::unique_ptr<Lane>> lanes_;
};

} // namespace tcs
