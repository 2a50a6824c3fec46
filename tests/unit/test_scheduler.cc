// Unit tests for the scheduling decision (coordinator/scheduler.h): who of
// the controllers behind the world's next step runs, in what order, how far,
// and when and how far the world steps instead (docs/DESIGN.md §2).
#include <cstdint>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "scheduler.h"
#include "tcs/vtime.h"

namespace {

using tcs::Contender;
using tcs::Decision;

constexpr int64_t kMs = 1000000;

Contender ready(int64_t v)
{
	Contender c;
	c.at = v;
	return c;
}

Contender running(int64_t v)
{
	Contender c = ready(v);
	c.running = true;
	return c;
}

Contender exited()
{
	Contender c;
	c.exited = true;
	return c;
}

Contender rechecking(int64_t at)
{
	Contender c = ready(at);
	c.rechecks = true;
	return c;
}

Decision decide(const std::vector<Contender> &cs, int64_t sim = 0, bool barrier = false)
{
	return tcs::decide(cs, sim, kMs, barrier);
}

void nobody_when_all_have_exited(void **)
{
	assert_int_equal(decide({}).kind, Decision::Nobody);
	assert_int_equal(decide({ exited(), exited() }).kind, Decision::Nobody);
}

void the_one_furthest_behind_runs_first(void **)
{
	// All three are behind the step at 1 ms; the earliest goes first, so
	// what it does there (a command, a signal) is in force for the later.
	Decision d = decide({ ready(700000), ready(200000), ready(500000) });
	assert_int_equal(d.kind, Decision::Run);
	assert_int_equal(d.who, 1);
	assert_int_equal(d.at, 200000);
}

void of_equals_the_first_in_order_runs(void **)
{
	Decision d = decide({ exited(), ready(300000), ready(300000) });
	assert_int_equal(d.kind, Decision::Run);
	assert_int_equal(d.who, 1);
}

void one_behind_runs_while_others_run(void **)
{
	// Another core's controller running does not hold back one behind.
	Decision d = decide({ running(100000), ready(900000) });
	assert_int_equal(d.kind, Decision::Run);
	assert_int_equal(d.who, 1);
}

void a_wait_ending_at_the_step_is_not_behind(void **)
{
	// A controller whose turn comes at the step boundary exactly runs
	// after the world has stepped there, not before.
	Decision d = decide({ ready(kMs), running(500000) });
	assert_int_equal(d.kind, Decision::Wait);
}

void the_world_steps_once_none_is_behind(void **)
{
	Decision d = decide({ ready(kMs), ready(kMs + 1) }, 0);
	assert_int_equal(d.kind, Decision::Step);
	assert_int_equal(d.to, kMs);
}

void steps_nobody_acts_in_are_skipped(void **)
{
	// The next event is at 7.5 ms: the world goes to the step before it,
	// 7 ms, in one go; the step to 8 ms is then the controller's.
	Decision d = decide({ ready(7500000), exited() }, 2 * kMs);
	assert_int_equal(d.kind, Decision::Step);
	assert_int_equal(d.to, 7 * kMs);
	// An event on a boundary: the world goes right up to it.
	d = decide({ ready(9 * kMs) }, 2 * kMs);
	assert_int_equal(d.to, 9 * kMs);
}

void a_recheck_each_step_skips_nothing(void **)
{
	// One that must be looked at every step (asleep outside the hooks)
	// forbids skipping, though its own turn is far.
	Decision d = decide({ ready(50 * kMs), rechecking(80 * kMs) }, 0);
	assert_int_equal(d.kind, Decision::Step);
	assert_int_equal(d.to, kMs);
}

void a_barrier_skips_nothing(void **)
{
	// With peers on other hosts each step is a barrier they answer.
	Decision d = decide({ ready(50 * kMs) }, 0, true);
	assert_int_equal(d.kind, Decision::Step);
	assert_int_equal(d.to, kMs);
}

void idle_when_every_one_waits_on_the_real_world(void **)
{
	Decision d = decide({ ready(TCS_NEVER), exited(), rechecking(TCS_NEVER) });
	assert_int_equal(d.kind, Decision::Idle);
}

void a_parent_waits_while_its_child_runs(void **)
{
	// The parent's wait for its child is due (at 0.5 ms), its child runs
	// on another core: the parent does not run, and the decision is to
	// wait (the child is stopped at the parent's time, run_until).
	Contender parent = ready(500000);
	parent.waits_on_running_child = true;
	Decision d = decide({ parent, running(300000) });
	assert_int_equal(d.kind, Decision::Wait);
	// Another behind the step runs meanwhile.
	d = decide({ parent, running(300000), ready(700000) });
	assert_int_equal(d.kind, Decision::Run);
	assert_int_equal(d.who, 2);
	std::vector<Contender> cs = { parent, running(300000) };
	assert_int_equal(tcs::run_until(cs, 1, kMs, -1), kMs);
	cs = { parent, ready(300000) };
	assert_int_equal(tcs::run_until(cs, 1, 0, -1), 500000);
}

void run_until_the_next_turn_of_another(void **)
{
	std::vector<Contender> cs = { ready(200000), ready(3500000), exited(), ready(TCS_NEVER) };
	// Not stopped at the step (1 ms) nobody needs: at 3.5 ms, the other's turn.
	assert_int_equal(tcs::run_until(cs, 0, kMs, -1), 3500000);
	// Never short of the step, though another's turn comes sooner.
	assert_int_equal(tcs::run_until(cs, 1, 4 * kMs, -1), 4 * kMs);
	// The run's end.
	assert_int_equal(tcs::run_until(cs, 0, kMs, 2 * kMs), 2 * kMs);
	// Alone, with no end: it may run on for ever (lockstep needs no budget).
	std::vector<Contender> alone = { ready(0), exited() };
	assert_int_equal(tcs::run_until(alone, 0, kMs, -1), TCS_NEVER);
}

void run_until_counts_those_running(void **)
{
	// One running on another core at 1.2 ms is a turn too: what it
	// commands may matter to this one.
	std::vector<Contender> cs = { ready(0), running(1200000) };
	assert_int_equal(tcs::run_until(cs, 0, kMs, -1), 1200000);
}

void run_until_the_next_look_at_one_asleep(void **)
{
	// One asleep outside the hooks, already looked at in this step (its
	// turn says never): the other runs to the step's end, not on for ever,
	// for the next look.
	Contender asleep = ready(TCS_NEVER);
	asleep.rechecks = true;
	std::vector<Contender> cs = { ready(200000), asleep };
	assert_int_equal(tcs::run_until(cs, 0, kMs, -1), kMs);
	// Its own re-checks do not hold it: it runs to the other's turn.
	cs = { ready(3500000), asleep };
	assert_int_equal(tcs::run_until(cs, 1, kMs, -1), 3500000);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(nobody_when_all_have_exited),
		cmocka_unit_test(the_one_furthest_behind_runs_first),
		cmocka_unit_test(of_equals_the_first_in_order_runs),
		cmocka_unit_test(one_behind_runs_while_others_run),
		cmocka_unit_test(a_wait_ending_at_the_step_is_not_behind),
		cmocka_unit_test(the_world_steps_once_none_is_behind),
		cmocka_unit_test(steps_nobody_acts_in_are_skipped),
		cmocka_unit_test(a_recheck_each_step_skips_nothing),
		cmocka_unit_test(a_barrier_skips_nothing),
		cmocka_unit_test(idle_when_every_one_waits_on_the_real_world),
		cmocka_unit_test(a_parent_waits_while_its_child_runs),
		cmocka_unit_test(run_until_the_next_turn_of_another),
		cmocka_unit_test(run_until_counts_those_running),
		cmocka_unit_test(run_until_the_next_look_at_one_asleep),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
