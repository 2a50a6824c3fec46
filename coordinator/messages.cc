// A controller's messages: read from its channels (the main one, a
// thread's) or its mailbox, checked (a controller is untrusted), and each
// handed to the part that serves it.
#include "messages.h"

#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>

#include <algorithm>
#include <cstring>

#include "asleep.h"
#include "children.h"
#include "clock_ns.h"
#include "device_requests.h"
#include "exits.h"
#include "record_replay.h"
#include "proc_info.h"
#include "signal_timers.h"
#include "signals.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"
#include "threads.h"
#include "transitions.h"
#include "waits.h"
#include "world_steps.h"

namespace tcs {

namespace {
// Messages a controller may send without an answer (see on_channel).
constexpr int kMaxUnanswered = 4;
} // namespace

// One message per call: the loop is level-triggered, so a channel with more
// comes back after the others had their turn. No channel may keep the
// coordinator from the others: a thread can always have its next request
// there by the time the last is answered.
void on_channel(Run &run, Controller &c, ThreadChannel *t)
{
	const int fd = t ? t->fd.get() : c.channel.get();
	ChannelState &st = t ? t->state : c.main_state;
	alignas(8) unsigned char buf[sizeof(struct tcs_msg) + 1];
	// A child or a thread registering passes its channel (SCM_RIGHTS); an
	// fd that comes with any other message is closed.
	struct tcs_msg_io io;
	tcs_msg_io_recv(&io, buf, sizeof buf);
	ssize_t n = recvmsg(fd, &io.mh, MSG_DONTWAIT | MSG_CMSG_CLOEXEC);
	if (n < 0 && (errno == EAGAIN || errno == EINTR))
		return;
	UniqueFd passed(n > 0 ? tcs_msg_io_fd(&io) : -1);
	if (n == 0 || (n < 0 && errno == ECONNRESET)) {
		run.devices.take_lazy_commands(c, -1, run.trace);
		// Every copy of this end is closed: the thread has ended, or the
		// controller is exiting (its pidfd tells when).
		if (t)
			thread_gone(run, c, t);
		else
			run.loop.remove(c.channel.get());
		return;
	}
	struct tcs_msg m;
	if (const char *why = tcs_msg_check(buf, (long)n, &m)) {
		run.devices.take_lazy_commands(c, -1, run.trace);
		drop(run, c, std::string("bad message on its channel: ") + why);
		return;
	}
	// What it posted in its mailbox came before anything that followed on
	// the channel (an EARLY from its parked wait, say).
	const bool took = !t && take_mailbox(run, c);
	if (!c.dropped.empty())
		return;
	if (m.type == TCS_MSG_DOORBELL) {
		// Rung for a request already taken while polling, or now.
		if (t)
			drop(run, c, "a DOORBELL on a thread's channel");
		else if (!took && ++st.unanswered > kMaxUnanswered)
			drop(run, c, "it rings without a request in its mailbox");
		return;
	}
	on_request(run, c, t, m, std::move(passed));
}

void on_request(Run &run, Controller &c, ThreadChannel *t, const ::tcs_msg &m, UniqueFd passed)
{
	const int fd = t ? t->fd.get() : c.channel.get();
	const pid_t tid = t ? t->tid : c.pid;
	ChannelState &st = t ? t->state : c.main_state;
	if (c.journal()) {
		drain_journal(run, c);   // what it read before it asked, in order
		check_departure(run, c); // a replay it left: live from this request on
	}
	// Records it wrote since its last request carry the time it has now,
	// before anything it asks moves that. (A device it asks to take what
	// it wrote: that request takes them, and judges them with its write.)
	run.devices.take_lazy_commands(c, m.type == TCS_MSG_DEV_SYNC && m.kind == TCS_SYNC_WRITE ? m.arg : -1, run.trace);
	if (!t && m.type == TCS_MSG_CHILD && !(m.flags & TCS_CHILD_PARENT)) {
		// From a new child, not from c: it waits on its own channel.
		on_child(run, c, m, std::move(passed));
		return;
	}
	if (!t && m.type == TCS_MSG_THREAD) {
		on_thread(run, c, m, std::move(passed));
		return;
	}
	// The preload waits for the answer to each request: its HELLO, one
	// request and the EARLY that may cross the answer (and one from another
	// thread ending its wait) are all it can have outstanding. More is a
	// flood.
	if (++st.unanswered > kMaxUnanswered) {
		drop(run, c, "it floods its channel (" + std::to_string(st.unanswered) + " messages without waiting for an answer)");
		return;
	}
	// A request answered at once from one thread while another's wait is
	// the controller's own: that wait becomes a side wait, keeping its
	// channel and sequence (the request's answer goes by the controller's
	// record, which it takes; a parent's nanosleep was lost so when its
	// other thread forked). The asker runs: the controller is no longer
	// Blocked but Ready, to be resumed.
	const bool takes_record = m.type != TCS_MSG_BLOCK && m.type != TCS_MSG_EARLY && m.type != TCS_MSG_HELLO;
	const bool demoted = takes_record && set_own_wait_aside(run, c, fd);
	on_message(run, c, m, fd, tid);
	if (demoted)
		schedule(run);
}

void on_message(Run &run, Controller &c, const ::tcs_msg &m, int fd, pid_t tid)
{
	if (c.state() == CtlState::Asleep)
		wake_from_asleep(run, c); // it woke by itself and asks something
	// A request answered at once (a HELLO is not answered), on its
	// thread's channel.
	if (m.type != TCS_MSG_BLOCK && m.type != TCS_MSG_EARLY && m.type != TCS_MSG_HELLO)
		serve_request(c, m.seq, fd);
	switch (m.type) {
	case TCS_MSG_HELLO:
		if (fd != c.channel.get()) {
			drop(run, c, "HELLO on a thread's channel");
			return;
		}
		if (m.arg != c.pid) {
			drop(run, c, "HELLO from pid " + std::to_string(m.arg) + " on pid " + std::to_string(c.pid) + "'s channel");
			return;
		}
		// Again after an exec (a new image, a new nonce): welcome.
		if (c.attached && m.v == c.hello_nonce) {
			drop(run, c, "it said HELLO twice");
			return;
		}
		c.attached = true;
		c.hello_nonce = m.v;
		if (c.parent_id != 0) { // a child after its exec
			std::string was = c.name;
			c.name = proc_name(c.pid, c.name);
			if (c.name != was)
				trace_controller(run, c);
		}
		c.main_state = ChannelState{}; // a new image owes nothing yet
		return;
	case TCS_MSG_BLOCK:
		on_block(run, c, m, fd, tid);
		return;
	case TCS_MSG_EARLY:
		on_early(run, c, m, fd);
		return;
	case TCS_MSG_DEV_OPEN:
		on_dev_open(run, c, m);
		return;
	case TCS_MSG_DEV_SYNC:
		on_dev_sync(run, c, m);
		return;
	case TCS_MSG_TIMER:
		on_timer(run, c, m);
		return;
	case TCS_MSG_CHILD:
		on_forked(run, c, m);
		return;
	case TCS_MSG_THREAD:
		drop(run, c, "THREAD on a thread's channel");
		return;
	case TCS_MSG_KILL:
		on_kill(run, c, m);
		return;
	}
}

// c's request posted in its mailbox, served; false if none.
bool take_mailbox(Run &run, Controller &c)
{
	alignas(8) unsigned char buf[sizeof(struct tcs_msg)];
	if (!c.mailbox.take(buf))
		return false;
	struct tcs_msg m;
	const char *why = tcs_msg_check(buf, sizeof buf, &m);
	if (!why && !tcs_mailbox_carries(m.type))
		why = "a request the mailbox does not carry";
	if (why) {
		run.devices.take_lazy_commands(c, -1, run.trace);
		drop(run, c, std::string("bad request in its mailbox: ") + why);
		return true;
	}
	on_request(run, c, nullptr, m, UniqueFd{});
	// Not answered at once: it waits on its channel, off its core, which
	// the coordinator may give to another controller meanwhile.
	c.mailbox.park();
	return true;
}

} // namespace tcs
