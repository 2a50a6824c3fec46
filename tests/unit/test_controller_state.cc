// Unit tests for a controller's transition table (coordinator/controller_state.h):
// every move from every state, the illegal ones included, against the table
// docs/ARCHITECTURE.md writes down.
#include <cstdio>
#include <optional>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "controller_state.h"

namespace {

using tcs::CtlMove;
using tcs::CtlState;

constexpr int kStates = 6, kMoves = 11;
constexpr CtlState kAllStates[kStates] = { CtlState::Ready, CtlState::Running, CtlState::Blocked,
					   CtlState::Asleep, CtlState::Dropped, CtlState::Exited };
constexpr CtlMove kAllMoves[kMoves] = { CtlMove::Resume, CtlMove::Block, CtlMove::Preempt, CtlMove::Ahead,
					 CtlMove::Wake, CtlMove::SetAside, CtlMove::StepAside, CtlMove::Awake,
					 CtlMove::End, CtlMove::Drop, CtlMove::Exit };

// The table as docs/ARCHITECTURE.md has it: a row per state, a column per
// move; '-' where the move is illegal, else the state it leads to
// (R ready, U running, B blocked, A asleep, D dropped, X exited).
//                                  Res Blk Pre Ahd Wak SAs StA Awk End Drp Ext
constexpr const char *kTable[kStates] = {
	/* ready   */ "U" "B" "-" "R" "R" "-" "-" "-" "U" "D" "X",
	/* running */ "-" "B" "R" "R" "-" "-" "A" "-" "U" "D" "X",
	/* blocked */ "-" "-" "-" "-" "R" "R" "-" "-" "U" "D" "X",
	/* asleep  */ "-" "-" "-" "-" "-" "-" "-" "R" "U" "D" "X",
	/* dropped */ "-" "-" "-" "-" "-" "-" "-" "-" "-" "D" "X",
	/* exited  */ "-" "-" "-" "-" "-" "-" "-" "-" "-" "-" "-",
};

std::optional<CtlState> from_letter(char l)
{
	switch (l) {
	case 'R': return CtlState::Ready;
	case 'U': return CtlState::Running;
	case 'B': return CtlState::Blocked;
	case 'A': return CtlState::Asleep;
	case 'D': return CtlState::Dropped;
	case 'X': return CtlState::Exited;
	}
	return std::nullopt;
}

void every_cell_matches_the_written_table(void **)
{
	int legal = 0;
	for (int s = 0; s < kStates; s++)
		for (int m = 0; m < kMoves; m++) {
			const auto want = from_letter(kTable[s][m]);
			const auto got = tcs::after(kAllStates[s], kAllMoves[m]);
			if (want != got)
				fail_msg("%s from %s: table says %c, code says %s", tcs::move_name(kAllMoves[m]),
					 tcs::state_name(kAllStates[s]), kTable[s][m], got ? tcs::state_name(*got) : "illegal");
			legal += got.has_value();
		}
	assert_int_equal(legal, 25); // (the letters above)
}

// What no controller may do, spelt out: each is a defect the coordinator
// must refuse rather than carry out.
void illegal_moves_are_refused(void **)
{
	assert_false(tcs::after(CtlState::Blocked, CtlMove::Resume).has_value()); // answered first (Wake)
	assert_false(tcs::after(CtlState::Running, CtlMove::Wake).has_value());   // a running one waits in nothing
	assert_false(tcs::after(CtlState::Blocked, CtlMove::Block).has_value());  // one request at a time
	assert_false(tcs::after(CtlState::Asleep, CtlMove::Resume).has_value());  // it wakes first
	assert_false(tcs::after(CtlState::Dropped, CtlMove::Resume).has_value()); // a dropped one never runs again
	assert_false(tcs::after(CtlState::Dropped, CtlMove::Wake).has_value());
	assert_false(tcs::after(CtlState::Dropped, CtlMove::End).has_value());
	assert_false(tcs::after(CtlState::Ready, CtlMove::Preempt).has_value()); // only a running one is stopped
	for (CtlMove m : kAllMoves)
		assert_false(tcs::after(CtlState::Exited, m).has_value()); // nothing follows an exit
}

// From any state but its end, a controller can always be dropped, end with
// the run or exit: nothing leaves it with no way out.
void every_live_state_has_a_way_out(void **)
{
	for (CtlState s : kAllStates) {
		if (s == CtlState::Exited)
			continue;
		assert_true(tcs::after(s, CtlMove::Exit) == CtlState::Exited);
		assert_true(tcs::after(s, CtlMove::Drop) == CtlState::Dropped);
	}
}

// A waiting state is left only by an answer or the controller's own waking
// (or its end): the scheduler never resumes one still waiting.
void waiting_states_are_left_by_an_answer(void **)
{
	for (CtlState s : kAllStates) {
		if (!tcs::waiting(s))
			continue;
		assert_false(tcs::after(s, CtlMove::Resume).has_value());
		assert_false(tcs::after(s, CtlMove::Preempt).has_value());
	}
	assert_true(tcs::waiting(CtlState::Blocked));
	assert_true(tcs::waiting(CtlState::Asleep));
	assert_false(tcs::waiting(CtlState::Dropped));
	assert_false(tcs::waiting(CtlState::Ready));
}

void names_are_distinct(void **)
{
	for (int a = 0; a < kStates; a++)
		for (int b = a + 1; b < kStates; b++)
			assert_string_not_equal(tcs::state_name(kAllStates[a]), tcs::state_name(kAllStates[b]));
	for (int a = 0; a < kMoves; a++)
		for (int b = a + 1; b < kMoves; b++)
			assert_string_not_equal(tcs::move_name(kAllMoves[a]), tcs::move_name(kAllMoves[b]));
}

} // namespace

int main()
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(every_cell_matches_the_written_table),
		cmocka_unit_test(illegal_moves_are_refused),
		cmocka_unit_test(every_live_state_has_a_way_out),
		cmocka_unit_test(waiting_states_are_left_by_an_answer),
		cmocka_unit_test(names_are_distinct),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
