// Signal timers (alarm, setitimer, timer_create in the controller): each
// signal goes when the controller's virtual time reaches the expiry. A
// computing controller's budget ends there: it is stopped and sent the
// signal, which waits for it to continue. A waiting one is woken with the
// signals to raise itself, inside its wait (sent from here, they could land
// between its request and its wait, where its handler would run unseen);
// its wait then returns EINTR if a handler ran.
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "coordinator.h"

namespace tcs {

void Coordinator::on_timer(Controller &c, const ::tcs_msg &m)
{
	restart_slice(c, m.cpu);
	c.wait.seq = m.seq;
	SignalTimer &t = c.timers[m.flags];
	t.signo = m.kind;
	t.tid = (int)m.v;
	t.next = m.deadline;
	t.interval = m.arg;
	c.timers_changed();
	deliver_due_timers(c);
	reply_now(c, 0);
	if (c.state == CtlState::Running)
		budget_to_next_timer(c);
}

namespace {

// Calls f with each timer due by c.v, then moves it past c.v: expirations
// that fell together are one signal, as pending signals of one kind are.
template <class F> void advance_due(Controller &c, F f)
{
	for (SignalTimer &t : c.timers) {
		if (t.next == TCS_NEVER || t.next > c.v)
			continue;
		f(t);
		t.next = t.interval > 0 ? t.next + ((c.v - t.next) / t.interval + 1) * t.interval : TCS_NEVER;
	}
	c.timers_changed();
}

} // namespace

// The signals the timers due owe, as bits (n - 1 for signal n): a waiting
// controller raises them itself, each to its timer's thread.
uint64_t Coordinator::due_timer_signals(Controller &c)
{
	uint64_t bits = 0;
	advance_due(c, [&](const SignalTimer &t) { bits |= 1ull << (t.signo - 1); });
	return bits;
}

// Sends the due signals to a controller that is not waiting (stopped, or
// about to run), each to the thread its timer names.
void Coordinator::deliver_due_timers(Controller &c)
{
	if (ending_)
		return;
	advance_due(c, [&](const SignalTimer &t) {
		if (t.tid > 0)
			syscall(SYS_tgkill, c.pid, t.tid, t.signo);
		else
			kill(c.pid, t.signo);
		c.count_raised_signal(); // (after: pending before it is counted)
	});
}

// Whether a wait with its own signal mask looked for pending signals before
// one of ours was raised (a preemption between its look and its BLOCK): the
// kernel would have ended it at once, so it must look again before any time
// passes (answered RECHECK at its own time).
bool Coordinator::missed_raised_signal(const Controller &c, const ::tcs_msg &m) const
{
	return (m.flags & TCS_BLOCK_SIGMASK) && (uint64_t)m.arg != c.raised_signals();
}

// A running controller's budget ends no later than its next timer (cpu mode:
// in lockstep it reaches it only by waiting). Budgets count from the
// slice's start, and so does the check's timer: armed from now for the
// whole budget, it came as late as the slice was old (a thread's 10 ms
// sleep beside a computing thread ended at 14 ms).
void Coordinator::budget_to_next_timer(Controller &c)
{
	int64_t at = std::min(c.next_timer(), side_next(c));
	Lane *lane = lanes_.of(c);
	if (cfg_.mode != TCS_MODE_CPU || at == TCS_NEVER || !lane)
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
