// The scheduling decision (docs/DESIGN.md §2, conservative synchronisation), as
// a pure function over what each controller is doing: who runs next and
// for how long, or whether the world steps, and how far. The coordinator
// gathers the contenders and carries the decision out (world_steps.cc);
// nothing here reads a clock or touches a process, so every case is
// unit-tested on its own (tests/unit/test_scheduler.cc).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace tcs {

// One controller as the decision sees it.
struct Contender {
	bool exited = false;
	bool running = false; // resumed: it reaches its budget's end by itself
	// When it next needs a core (TCS_NEVER: only something outside the
	// world can wake it): its virtual time if ready, else when its wait ends.
	int64_t at = 0;
	// Blocked in a wait that only a re-check each step can see end.
	bool rechecks = false;
	// Waits for a child of its own that is running: it does not run till
	// that child has stopped, for once awake it looks for ended children
	// in the kernel, which would show it one that ended on another core
	// before the child's end in virtual time (and before tcs had read the
	// child's last CPU, gone once it is reaped).
	bool waits_on_running_child = false;
};

struct Decision {
	enum Kind {
		Nobody, // no controller is alive
		Run,    // `who` is behind the next step: it runs, from `at`
		Wait,   // those running reach the next step first
		Idle,   // every one waits on the real world: time passes at real-time speed
		Step,   // nobody can run before `to`: the world steps there
	};
	Kind kind = Nobody;
	size_t who = 0;
	int64_t at = 0;
	int64_t to = 0;
};

// The world is at sim_ns and steps by step_ns. With `barrier` (peers on
// other hosts take part), every step is taken, none skipped.
Decision decide(std::span<const Contender> cs, int64_t sim_ns, int64_t step_ns, bool barrier);

// How far `who` may run before someone else needs the core: another's next
// turn or the run's end (duration_ns; < 0: none); never short of the step
// boundary `target`; one looked at each step (rechecks) is looked at next
// at the step's end, whatever its `at` says (a controller asleep outside
// the hooks may have woken meanwhile: while one ran on alone, a reader
// woken by its write learnt of it 400 ms late). Stopping a controller costs it real CPU (the timer
// interrupt, the stop and the continue run on its account), so it is not
// stopped at boundaries nobody needs.
int64_t run_until(std::span<const Contender> cs, size_t who, int64_t target, int64_t duration_ns);

} // namespace tcs
