// Signal timers (alarm, setitimer, timer_create in the controller): each
// signal goes when the controller's virtual time reaches the expiry. A
// computing controller's budget ends there: it is stopped and sent the
// signal, which waits for it to continue. A waiting one is woken with the
// signals to raise itself, inside its wait (sent from here, they could land
// between its request and its wait, where its handler would run unseen);
// its wait then returns EINTR if a handler ran. (Which timers are due, and
// raising them: the Controller's own, controller.cc.)
#include "signal_timers.h"

#include <algorithm>
#include <cmath>

#include "device_requests.h"
#include "slices.h"

namespace tcs {

void on_timer(Run &run, Controller &c, const ::tcs_msg &m)
{
	restart_slice(run, c, m.cpu);
	SignalTimer &t = c.timers[m.flags];
	t.signo = m.kind;
	t.tid = (int)m.v;
	t.next = m.deadline;
	t.interval = m.arg;
	c.timers_changed();
	if (!run.ending)
		c.raise_due_timers();
	// (Before the answer: a lockstep spin after it stops at the timer.)
	if (c.state() == CtlState::Running)
		budget_to_next_timer(run, c);
	reply_now(run, c, 0);
}

// A running controller's budget ends no later than its next timer (cpu mode;
// in lockstep, its spins stop there: spin_limit). Budgets count from the
// slice's start, and so does the check's timer: armed from now for the
// whole budget, it came as late as the slice was old (a thread's 10 ms
// sleep beside a computing thread ended at 14 ms).
void budget_to_next_timer(Run &run, Controller &c)
{
	if (run.cfg.mode == TCS_MODE_LOCKSTEP) {
		// (Replaying: the world steps where the record's stops were.)
		c.limit_spin(std::min(c.spin_limit(), run.replaying ? c.next_timer() : spin_limit(run, c)));
		return;
	}
	int64_t at = std::min(c.next_timer(), c.side_next());
	Lane *lane = run.lanes.of(c);
	if (at == TCS_NEVER || !lane)
		return;
	int64_t need = std::max<int64_t>((int64_t)std::ceil((double)(at - c.slice().v_base) / c.scale), 1);
	if (c.budgeted && need >= c.budget)
		return;
	c.budget = need;
	c.budgeted = true;
	c.checked_used = -1;
	c.check_interval = std::max(c.slice_wall + c.budget + c.lag_ns - wall_now(), kMinSlice);
	lane->budget.arm(c.check_interval);
}

} // namespace tcs
