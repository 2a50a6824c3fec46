// Threads of a controller (protocol.h, Threads). One controller is one
// virtual CPU whatever its threads: its virtual time advances only while
// none of them can run. Each thread waits on a channel of its own; a wait
// that begins while another thread can still run is a side wait, and the
// controller runs on. When the last runnable thread waits, the controller
// is Blocked in that wait (its "own" wait, served as a single thread's
// always was) with the side waits beside it; it is woken at the earliest of
// them all, and only the waits due then end. Threads asleep in the kernel
// outside tcs's hooks (a mutex, a pipe) count as waiting for something
// only another thread (or the outside world) can end: a Blocked controller
// with such threads is looked at each step, and runs again when one wakes.
#include "threads.h"

#include <sys/socket.h>

#include <algorithm>

#include "asleep.h"
#include "device_requests.h"
#include "exits.h"
#include "messages.h"
#include "proc_info.h"
#include "signal_timers.h"
#include "slices.h"
#include "tcs/msg_io.h"
#include "waits.h"
#include "world_steps.h"
#include "transitions.h"

namespace tcs {

namespace {
// Threads with a channel of their own, at once, per controller.
constexpr size_t kMaxThreads = 1024;
// How long a thread without a channel is taken for one still starting.
constexpr int64_t kThreadStartGrace = 50 * TCS_NS_PER_MS;
} // namespace

void on_thread(Run &run, Controller &c, const ::tcs_msg &m, UniqueFd channel)
{
	pid_t tid = (pid_t)m.arg;
	if (!channel) {
		drop(run, c, "THREAD without a channel");
		return;
	}
	if (!proc_has_thread(c.pid, tid)) {
		// A thread that ended as soon as it had sent this (its first
		// request done) has nothing left to keep; a tid alive elsewhere is
		// a lie.
		if (proc_task_exists(tid))
			drop(run, c, "THREAD for " + std::to_string(tid) + ", not one of its threads");
		return;
	}
	for (auto &t : c.threads)
		if (t->tid == tid) {
			thread_gone(run, c, t.get()); // a tid used again: the old one has ended
			break;
		}
	if (c.threads.size() >= kMaxThreads) {
		drop(run, c, "more than " + std::to_string(kMaxThreads) + " of its threads wait at once");
		return;
	}
	c.thread_first_seen.erase(tid);
	auto t = std::make_unique<ThreadChannel>();
	t->tid = tid;
	t->fd = std::move(channel);
	ThreadChannel *raw = t.get();
	Controller *cp = &c;
	c.threads.push_back(std::move(t));
	if (auto s = run.loop.add(raw->fd.get(), [&run, cp, raw](uint32_t) { on_channel(run, *cp, raw); }); !s)
		run.fatal = s;
}

void thread_gone(Run &run, Controller &c, ThreadChannel *t)
{
	int fd = t->fd.get();
	run.loop.remove(fd);
	c.side_waits.erase(std::remove_if(c.side_waits.begin(), c.side_waits.end(), [fd](const Request &w) { return w.fd == fd; }),
		     c.side_waits.end());
	if (c.wait.fd == fd) {
		c.wait.fd = -1;
		c.wait.active = false;
	}
	c.threads.erase(std::remove_if(c.threads.begin(), c.threads.end(), [t](const auto &p) { return p.get() == t; }),
			c.threads.end());
}

// A thread's BLOCK while another thread of c can still run: it waits beside
// the controller, which goes on. False if no other thread can run (the
// controller then blocks in this wait).
bool side_wait(Run &run, Controller &c, const ::tcs_msg &m, int fd, pid_t tid)
{
	// Stopped (preempted as this thread began its wait), its threads cannot
	// be told apart: assume the others run; if they do not, its budget's
	// check finds them all waiting (block_if_all_waiting).
	if (c.state() == CtlState::Running && runnable_threads(run, c, tid) == 0)
		return false;
	// (Its time may be past c.v(): a running controller's is settled only as
	// its slice ends.)
	c.side_waits.push_back(request_of(m, fd, tid, request_v(run, c, m), run.sim_ns, run.cfg.slack));
	if (c.state() == CtlState::Running) {
		budget_to_next_timer(run, c); // (and to the earliest side wait)
		if (!c.budgeted)
			arm_watchdog(run, c);
	}
	return true;
}

// Whether a thread's channel holds a request we have not read yet.
static bool has_unread_message(int fd)
{
	unsigned char b;
	return recv(fd, &b, 1, MSG_PEEK | MSG_DONTWAIT) > 0;
}

bool request_unread(const Controller &c)
{
	if (c.mailbox.requested() || (c.channel && has_unread_message(c.channel.get())))
		return true;
	for (const auto &t : c.threads)
		if (has_unread_message(t->fd.get()))
			return true;
	return false;
}

// The requests c's threads have sent and we have not read, heard before
// time passes for it. Running on a core of their own (not below the
// coordinator on its core), nothing orders one thread's requests before
// another's as we read them: an EARLY a thread sent to end another's wait,
// then its own BLOCK, may be read BLOCK first, and time would pass to that
// BLOCK's deadline before the EARLY was heard. The handlers' scheduling
// waits for the last of them (schedule() then decides once).
void hear_threads(Run &run, Controller &c)
{
	if (run.hearing_threads || !c.multithreaded())
		return;
	run.hearing_threads = true;
	for (int round = 0; round < 8 && c.state() != CtlState::Exited && c.dropped.empty(); round++) {
		bool any = false;
		if (c.channel && has_unread_message(c.channel.get())) {
			on_channel(run, c, nullptr);
			any = true;
		}
		// (Serving one may end a thread: by index, looked up again.)
		for (size_t i = 0; i < c.threads.size() && c.dropped.empty(); i++) {
			if (!has_unread_message(c.threads[i]->fd.get()))
				continue;
			on_channel(run, c, c.threads[i].get());
			any = true;
		}
		if (!any)
			break;
	}
	run.hearing_threads = false;
}

// How many threads of c could run now, leaving out `also` and those that
// have sent a wait: one preempted by us right after its send is still
// runnable for the kernel, on its way to its wait. Counted as runnable, it
// would make the last thread's wait a side wait too, and the controller
// would hold the core with every thread waiting until the watchdog looked.
// A thread asleep with a request on its channel that we have not read yet
// (it waits for the answer) is on its way to a wait too: taken for asleep
// outside the hooks, time would pass before its request was heard.
// A thread that has never waited through tcs (it has no channel yet) and
// sleeps may be one just started, on its way to its first wait: it counts
// as runnable for this long after it is first seen (wall time), so that no
// virtual time passes before it is counted. One that stays asleep outside
// tcs's hooks (a real read, say) is taken for asleep after that.
int runnable_threads(Run &run, Controller &c, pid_t also)
{
	std::vector<pid_t> waiting;
	waiting.reserve(c.side_waits.size() + 2);
	waiting.push_back(also);
	if (c.wait.active)
		waiting.push_back(c.wait.tid);
	for (const Request &w : c.side_waits)
		waiting.push_back(w.tid);
	int64_t now = -1;
	int runnable = 0;
	for (const ThreadState &t : proc_thread_states(c.pid)) {
		if (std::find(waiting.begin(), waiting.end(), t.tid) != waiting.end())
			continue;
		if (t.state == 'R') {
			runnable++;
			continue;
		}
		int channel = t.tid == c.pid ? c.channel.get() : -1;
		for (const auto &ch : c.threads)
			if (ch->tid == t.tid)
				channel = ch->fd.get();
		if (channel >= 0) {
			// A request not yet read (the main thread's in its mailbox
			// too): it waits for us, and runs once answered.
			if (has_unread_message(channel) || (t.tid == c.pid && c.mailbox.requested()))
				runnable++;
			continue;
		}
		if (now < 0)
			now = wall_now();
		auto [seen, fresh] = c.thread_first_seen.try_emplace(t.tid, now);
		if (now - seen->second < kThreadStartGrace)
			runnable++;
	}
	return runnable;
}

// Someone must raise c's timer signals due at `at` inside a wait: the
// thread a timer names, if it waits, else its own wait's, else the first
// waiting one. A signal raised into another waiting thread would end that
// one's wait only as the kernel got round to it, after the raiser may have
// waited again and let virtual time pass (up to a wait late, in lockstep).
static void choose_raiser(Run &run, Controller &c, int64_t at)
{
	pid_t tid = c.due_timer_thread(at);
	auto target = std::find_if(c.side_waits.begin(), c.side_waits.end(), [&](const Request &w) { return tid > 0 && w.tid == tid; });
	if (target == c.side_waits.end() && (c.wait.active || c.side_waits.empty()))
		return;
	if (target == c.side_waits.end())
		target = c.side_waits.begin();
	Request raiser = *target;
	c.side_waits.erase(target);
	own_wait_beside(run, c);
	own_wait_from(c, raiser);
}

// c is Blocked with several waiting threads (or threads asleep outside the
// hooks): ends what is due at `at`, after which it is Ready. False when
// nothing is due and no thread woke by itself: it stays Blocked.
bool wake_threads(Run &run, Controller &c, int64_t at)
{
	int64_t v = std::max(c.v(), at);
	bool woke_alone = c.others_asleep && runnable_threads(run, c, 0) > 0;
	bool timer = c.next_timer() <= v;
	if (timer && raise_timers_in_read(c, v))
		timer = false;
	bool own = c.wait.active && !c.sync &&
		   (c.wait.deadline <= v || c.wait.signalled_at <= v || (c.wait.recheck && c.wait.rechecked_at < run.sim_ns) ||
		    (c.wait.devices && next_record_due(c) <= v));
	bool side = std::any_of(c.side_waits.begin(), c.side_waits.end(), [&](const Request &w) { return c.side_due(w, v, run.sim_ns); });
	// Its own record due though no request of its own is held (its last
	// was answered, its threads waited on): it runs, or it would be first
	// in line at that time for ever.
	bool stale = !c.wait.active && !c.sync && c.wait.deadline <= v;
	// A device read waiting for its record, which is due (complete_sync).
	bool read_due = c.sync && c.wait.deadline <= v;
	if (!woke_alone && !timer && !own && !side && !stale && !read_due) {
		forget_signal(c); // (the thread it reached was asleep: looked at each step)
		return false;
	}
	c.others_asleep = false;
	if (timer && !c.sync)
		choose_raiser(run, c, v);
	if (timer && c.wait.active && !c.sync) {
		advance(c, v);
		wake(run, c, v, TCS_WAKE_SIGNAL, (int64_t)c.take_due_timer_signals());
	} else if (own) {
		bool due = c.wait.deadline <= v;
		wake(run, c, v, due || c.wait.devices ? TCS_WAKE_DEADLINE : TCS_WAKE_RECHECK);
	} else if (!c.sync) {
		own_wait_beside(run, c);
		advance(c, v);
		move(run, c, CtlMove::SetAside);
	} else {
		advance(c, v);
		move(run, c, CtlMove::Wake); // a device read: complete_sync decides
	}
	looked_at(run, c, true);
	return true;
}

void answer_side(Run &run, Controller &c, const Request &w)
{
	c.channel_state(w.fd).unanswered = 0;
	struct tcs_msg m = tcs_msg_make(TCS_MSG_WAKE, w.seq);
	m.kind = w.reason;
	m.v = c.v();
	m.arg = w.result;
	send_answer(run, c, w.fd, m, -1);
	if (run.trace.is_open())
		run.trace.wait(c.id, w.kind, w.requested_at, w.asked, c.v(), w.absolute());
}

// Ends the side waits due at c's time (as it is resumed, its sensors'
// records delivered).
void end_side_waits(Run &run, Controller &c)
{
	for (size_t i = 0; i < c.side_waits.size();) {
		Request &w = c.side_waits[i];
		if (!c.side_due(w, c.v(), run.sim_ns)) {
			if (w.flags & TCS_BLOCK_RECHECK)
				w.rechecked_at = run.sim_ns;
			i++;
			continue;
		}
		if (w.reason == 0)
			w.reason = w.deadline <= c.v() || (w.flags & TCS_BLOCK_DEVICES) ? TCS_WAKE_DEADLINE : TCS_WAKE_RECHECK;
		if (w.deadline != TCS_NEVER && w.deadline <= c.v())
			w.reason = TCS_WAKE_DEADLINE;
		Request done = w;
		c.side_waits.erase(c.side_waits.begin() + (long)i);
		answer_side(run, c, done);
	}
}

// At the end of the run every wait ends at once.
void end_all_side_waits(Run &run, Controller &c)
{
	for (Request &w : c.side_waits) {
		w.reason = TCS_WAKE_DEADLINE;
		answer_side(run, c, w);
	}
	c.side_waits.clear();
}

// A running controller with waiting threads, found making no progress: if
// none of its threads can run, it is Blocked beside their waits.
bool block_if_all_waiting(Run &run, Controller &c)
{
	if (c.side_waits.empty() || c.new_child.pid != 0 || runnable_threads(run, c, 0) > 0)
		return false;
	int64_t cpu = c.cpu_now();
	run.lanes.leave(c);
	c.account(cpu, run.cfg.mode);
	c.publish_slice(cpu);
	trace_slice_end(run, c, "blocked", cpu);
	c.cpu_at_end = cpu;
	own_wait_beside(run, c);
	block(run, c, {});
	c.others_asleep = proc_thread_count(c.pid) > (int)c.side_waits.size();
	schedule(run);
	return true;
}

} // namespace tcs
