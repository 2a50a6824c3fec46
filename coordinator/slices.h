// Slices: budgets, checks, preemption, accounting (slices.cc), as functions
// over the run's state (run.h).
#pragma once

#include "run.h"

namespace tcs {

void resume(Run &run, Controller &c, int64_t target, int lane);
// cpu mode: c runs without a budget (it was alone when resumed) and now
// others wait for the world: it gets one, to target.
void budget_to(Run &run, Controller &c, int64_t target);
void on_budget(Run &run, Lane &lane);
// SIGSTOP, and wait till it has stopped: false if it died first. What the
// stop costs it is left out of its slice, as its continuation's is by
// let_go() (SIGCONT).
bool hold_still(Run &run, Controller &c);
void let_go(Run &run, Controller &c);
// Ends the slice of c, held still (hold_still): judged held, as only then
// is its CPU clock exact and what its slice leaves out known.
void preempt(Run &run, Controller &c);
bool wait_until_stopped(Run &run, Controller &c);
// cpu: the process's CPU clock at the end; budget and overshoot: of a
// preempted slice (real CPU).
void trace_slice_end(Run &run, Controller &c, const char *why, int64_t cpu, int64_t budget = -1, int64_t overshoot = 0);
int64_t wall_now();
// c's accounting slice begins now, in its lane: the wall time (and, sharing
// our core, our own CPU) that its checks set its CPU against.
void start_slice_clock(Run &run, Controller &c);
// Lockstep: how far a spin of c's may take it (the page's spin_limit): to
// the world's next step after its time (what it reads then must see that
// step), its next timer, or another of its threads' wake.
int64_t spin_limit(const Run &run, const Controller &c);
// The CPU a request charges up to; a claim may exceed the wall time
// since the slice began by this much (the hook's part before we ran).
int64_t charge_point(Run &run, Controller &c, int64_t claimed);
// When a request of a running controller's thread was made: its own
// claim, no earlier than c.v() nor later than its process's time as the
// request is heard (other threads may have run since). c.v() unless
// running in cpu mode.
int64_t request_v(Run &run, Controller &c, const ::tcs_msg &m);

} // namespace tcs
