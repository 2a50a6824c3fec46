// The one writer of a controller's state (controller_state.h's table): every
// change of it is a move made here, checked against the table.
#pragma once

#include "run.h"

namespace tcs {

// Makes move m of c, if the table allows it from c's state; else says so
// once (a defect of tcs) and leaves c as it is. True if made.
bool move(Run &run, Controller &c, CtlMove m);
// c's request is answered, for `reason` (TCS_WAKE_*) with `result`: its
// WAKE is owed (sent as it resumes, or now by answer()).
void owe_answer(Controller &c, uint16_t reason, int64_t result);
// c's virtual time moves on to `at` (never back).
void advance(Controller &c, int64_t at);
// c starts at `at`, behind where it stood or not: a new controller, a child
// not yet run, a replay's recorded end.
void place_at(Controller &c, int64_t at);
// What c waits in ends at v (at least): it is Ready, its answer owed.
void wake(Run &run, Controller &c, int64_t v, uint16_t reason, int64_t result = 0);

} // namespace tcs
