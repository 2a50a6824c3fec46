// A controller's transitions: the one writer of its state (every change a
// move checked against controller_state.h's table), of its virtual time
// (besides account(), as a slice closes) and, but for a few fields, of the
// request it serves and what ends its wait.
#pragma once

#include "run.h"

namespace tcs {

// Makes move m of c, if the table allows it from c's state; else says so
// once (a defect of tcs) and leaves c as it is. True if made.
bool move(Run &run, Controller &c, CtlMove m);
// c serves request seq of the thread on channel fd (-1: the main one): its
// answer goes back there, at once or later.
void serve_request(Controller &c, uint32_t seq, int fd);
// What ends a waiting controller's wait, besides an answer to its request.
struct WaitEnds {
	int64_t deadline = TCS_NEVER; // its timeout
	bool recheck = false;         // a re-check at each step
	bool devices = false;         // a record due on one of its sensors
	bool for_child = false;       // a child's end
};
// c waits until `ends` says (Blocked; Asleep, moved by StepAside), looked
// at last now, in no wait of the program's.
void block(Run &run, Controller &c, const WaitEnds &ends, CtlMove how = CtlMove::Block);
// c waits in its program's wait r.
void block_in(Run &run, Controller &c, const Request &r, const WaitEnds &ends);
// An asleep controller woke (or asked something): no longer looked at each
// step.
void awake(Run &run, Controller &c);
// The scheduler looked at c's wait now, and at the signal sent to it, if
// `signal_too` (a re-check each step counts from here).
void looked_at(Run &run, Controller &c, bool signal_too = false);
// The signal sent to c while it waited has been looked at.
void forget_signal(Controller &c);
// The controller's own wait becomes a side wait: it goes on waiting while
// other threads run (an answer owed to it goes with it).
void own_wait_beside(Run &run, Controller &c);
// A side wait becomes the controller's own.
void own_wait_from(Controller &c, const Request &w);
// A request that takes the controller's record of its last request (to be
// answered on channel fd) while another thread's wait is its own: that
// wait becomes a side wait, keeping its channel and sequence, and the
// controller, a thread of which runs, is no longer Blocked but Ready (to
// be scheduled). True if so.
bool set_own_wait_aside(Run &run, Controller &c, int fd);
// c's request is answered, for `reason` (TCS_WAKE_*) with `result`: its
// WAKE is owed (sent as it resumes, or now by answer()).
void owe_answer(Controller &c, uint16_t reason, int64_t result);
// c's virtual time moves on to `at` (never back).
void advance(Controller &c, int64_t at);
// c starts at `at`, behind where it stood or not: a new controller, a child
// not yet run, a replay's recorded end.
void place_at(Controller &c, int64_t at);
// c's answer has gone: nothing is owed, and the fd it passed is closed.
void answered(Controller &c);
// What c waits in ends at v (at least): it is Ready, its answer owed.
void wake(Run &run, Controller &c, int64_t v, uint16_t reason, int64_t result = 0);

} // namespace tcs
