// A controller's waits: a BLOCK taken (on_block), ended before it began
// (on_early), and the WAKE that ends it (wake, send_wake, send_answer).
#include "waits.h"

#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>

#include "children.h"
#include "clock_ns.h"
#include "exits.h"
#include "record_replay.h"
#include "proc_info.h"
#include "slices.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"
#include "threads.h"
#include "world_steps.h"
#include "transitions.h"

namespace tcs {

// Every WAKE goes out here: through c's mailbox if the request came that
// way and c still spins for it, else on channel fd (with pass_fd, if not
// -1). A full or closed channel means the controller is gone or hostile;
// its pidfd or its next message will tell.
void send_answer(Run &run, Controller &c, int fd, const ::tcs_msg &m, int pass_fd)
{
	if (fd == c.channel.get()) {
		if (pass_fd >= 0)
			c.mailbox.park(); // (an fd only the channel can carry)
		if (c.mailbox.answer(m))
			return;
	}
	struct tcs_msg_io io;
	tcs_msg_io_send(&io, &m, sizeof m, pass_fd);
	(void)sendmsg(fd, &io.mh, MSG_DONTWAIT | MSG_NOSIGNAL);
}

void send_wake(Run &run, Controller &c)
{
	int fd = c.wait.fd >= 0 ? c.wait.fd : c.channel.get();
	c.channel_state(fd).unanswered = 0;
	struct tcs_msg m = tcs_msg_make(TCS_MSG_WAKE, c.wait.seq);
	m.kind = c.wait.reason;
	m.flags = TCS_WAKE_STARTS_SLICE;
	m.v = c.v();
	m.arg = c.wait.result;
	m.deadline = c.wait.requested_at; // (what a recording controller journals: tcs/journal.h)
	if (&c != run.ctls.front().get() || ++run.first_wakes != run.cfg.realtime.lose_wake)
		send_answer(run, c, fd, m, c.wait.pass_fd);
	if (c.wait.active && run.trace.is_open())
		run.trace.wait(c.id, c.wait.kind, c.wait.requested_at, c.wait.asked, c.v(), c.wait.absolute());
	answered(c);
}

void answer(Run &run, Controller &c)
{
	if (c.state() == CtlState::Ready && c.woke_unheld) {
		schedule(run); // (resume sends it)
		return;
	}
	send_wake(run, c);
}

void on_block(Run &run, Controller &c, const ::tcs_msg &m, int fd, pid_t tid)
{
	if (replay_stop(run, c, m, fd, tid))
		return;
	ChannelState &st = c.channel_state(fd);
	if (!run.ending && st.early_before_block != 0 && st.early_before_block == m.seq) {
		// Another thread ended this wait before it began.
		st.early_before_block = 0;
		c.stats.count_wait(m);
		Request w = request_of(m, fd, tid, c.v(), run.sim_ns, run.cfg.slack);
		w.reason = TCS_WAKE_EARLY;
		answer_side(run, c, w);
		if (c.state() == CtlState::Blocked) {
			// (It was asleep outside the hooks: it runs again.)
			own_wait_beside(run, c);
			move(run, c, CtlMove::SetAside);
			schedule(run);
		}
		return;
	}
	if (run.ending) {
		// The run is over: every wait ends at once so SIGTERM can act.
		serve_request(c, m.seq, fd);
		if (m.deadline != TCS_NEVER)
			advance(c, m.deadline);
		owe_answer(c, TCS_WAKE_DEADLINE, 0);
		send_wake(run, c);
		return;
	}
	if (c.state() == CtlState::Blocked) {
		if (c.wait.active && fd == (c.wait.fd >= 0 ? c.wait.fd : c.channel.get())) {
			drop(run, c, "it asked to wait while already waiting");
			return;
		}
		// A thread that was asleep outside the hooks woke and waits now.
		c.side_waits.push_back(request_of(m, fd, tid, c.v(), run.sim_ns, run.cfg.slack));
		if (c.missed_raised_signal(m))
			c.side_waits.back().reason = TCS_WAKE_RECHECK;
		child_wait_begins(run, c, m, &c.side_waits.back());
		c.stats.count_wait(m);
		hear_threads(run, c);
		schedule(run);
		return;
	}
	if (c.multithreaded() && side_wait(run, c, m, fd, tid)) {
		child_wait_begins(run, c, m, &c.side_waits.back());
		c.stats.count_wait(m);
		if (m.flags & TCS_BLOCK_ABSOLUTE) {
			c.stats.absolute_waits++;
			if (m.deadline <= c.side_waits.back().requested_at)
				c.stats.reported_misses++;
		}
		if (c.missed_raised_signal(m))
			c.side_waits.back().reason = TCS_WAKE_RECHECK;
		// Ended as it began (a signal raised unseen, a child already
		// ended): answered now, while the controller runs; stopped, it is
		// answered as it resumes. Its other threads may compute on
		// without a budget: nothing else would come to end it.
		if (c.side_waits.back().reason && c.state() == CtlState::Running) {
			// (At the time its process has reached, as on_early's.)
			if (run.cfg.mode == TCS_MODE_CPU)
				c.account(charge_point(run, c, m.cpu), run.cfg.mode);
			Request w = c.side_waits.back();
			c.side_waits.pop_back();
			answer_side(run, c, w);
		}
		return;
	}
	if (c.state() == CtlState::Running) {
		run.lanes.leave(c);
		// Charged up to the hook's entry (see charge_point).
		int64_t cpu = charge_point(run, c, m.cpu);
		c.account(cpu, run.cfg.mode);
		trace_slice_end(run, c, "blocked", cpu);
		c.cpu_at_end = cpu;
	}
	// (Ready: the budget ran out just as it began to wait; SIGSTOP has
	// already closed its slice.)
	c.stats.count_wait(m);
	if (m.flags & TCS_BLOCK_ABSOLUTE) {
		c.stats.absolute_waits++;
		if (m.deadline <= c.v())
			c.stats.reported_misses++; // TCS_PAGE_REPORT_MISSES
	}
	const Request r = request_of(m, fd, tid, c.v(), run.sim_ns, run.cfg.slack);
	block_in(run, c, r,
		 { .deadline = r.deadline,
		   .recheck = (m.flags & TCS_BLOCK_RECHECK) != 0,
		   .devices = (m.flags & TCS_BLOCK_DEVICES) != 0,
		   .for_child = (m.flags & TCS_BLOCK_CHILD) != 0 });
	// Threads asleep outside the hooks: looked at each step (threads.cc).
	c.others_asleep = c.multithreaded() && proc_thread_count(c.pid) > 1 + (int)c.side_waits.size();
	child_wait_begins(run, c, m, nullptr);
	if (c.missed_raised_signal(m))
		wake(run, c, c.v(), TCS_WAKE_RECHECK);
	hear_threads(run, c);
	schedule(run);
}

void on_early(Run &run, Controller &c, const ::tcs_msg &m, int fd)
{
	if (run.ending)
		return;
	if (c.state() == CtlState::Blocked && c.wait.active && m.seq == c.wait.seq &&
	    fd == (c.wait.fd >= 0 ? c.wait.fd : c.channel.get())) {
		// A signal another controller sent (told before it was sent)
		// ends the wait at the sender's time: its handler runs then.
		int64_t at = std::max(c.v(), run.sim_ns);
		if (m.kind == TCS_EARLY_SIGNAL && c.wait.signalled_at != TCS_NEVER)
			at = std::max(at, c.wait.signalled_at);
		wake(run, c, at, TCS_WAKE_EARLY);
		schedule(run);
		return;
	}
	if (c.sync && c.state() != CtlState::Running && m.seq == c.wait.seq &&
	    fd == (c.wait.fd >= 0 ? c.wait.fd : c.channel.get())) {
		// A handler ran inside a device read still waiting for its record
		// (a timer's signal raised in it): the read's wait ends at the
		// signal's time, not at the next record, so that what the handler
		// asks for (a wait) begins then; the read itself goes on after it
		// (device_requests.c).
		c.sync.reset();
		wake(run, c, std::max(c.v(), run.sim_ns), TCS_WAKE_EARLY);
		schedule(run);
		return;
	}
	for (size_t i = 0; i < c.side_waits.size(); i++) {
		Request &w = c.side_waits[i];
		if (w.fd != fd || w.seq != m.seq)
			continue;
		w.reason = TCS_WAKE_EARLY;
		if (c.state() == CtlState::Running) {
			// Ended by a thread that runs: at that thread's time now (in
			// cpu mode past the slice's start by what it has computed), so
			// that what it did is never seen as done before it was.
			if (run.cfg.mode == TCS_MODE_CPU)
				c.account(charge_point(run, c, m.cpu), run.cfg.mode);
			Request done = w;
			c.side_waits.erase(c.side_waits.begin() + (long)i);
			answer_side(run, c, done);
		} else if (c.state() == CtlState::Blocked && wake_threads(run, c, std::max(c.v(), run.sim_ns))) {
			schedule(run);
		}
		return; // (Ready: answered as it resumes)
	}
	// Not waiting (yet): another thread ended the wait this seq will be,
	// or the answer crossed it. Either way it is owed nothing.
	// (One such is not counted against a flood: a thread may be woken
	// just as its wait returns without asking.)
	ChannelState &st = c.channel_state(fd);
	if (st.early_before_block == 0)
		st.unanswered = std::max(0, st.unanswered - 1);
	st.early_before_block = m.seq;
}

} // namespace tcs
