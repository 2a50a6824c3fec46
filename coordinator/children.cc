// Children of controllers (fork, vfork, posix_spawn, exec): each becomes a
// controller of its own when it registers on its parent's channel; a
// parent waits for its new child to register, and an exec under way is
// looked at until the new image says HELLO (docs/DESIGN.md §3).
#include "children.h"

#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>

#include <algorithm>
#include <cstring>

#include "asleep.h"
#include "world_steps.h"
#include "clock_ns.h"
#include "device_requests.h"
#include "exits.h"
#include "messages.h"
#include "proc_info.h"
#include "slices.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"
#include "threads.h"
#include "waits.h"
#include "transitions.h"

namespace tcs {

namespace {
// How long a child may run unregistered before it is said to run in real
// time (a program still loading has not registered yet).
constexpr int64_t kRegistrationGrace = 200 * TCS_NS_PER_MS;
// How often a child's exec, still under way, is looked at (wall time).
constexpr int64_t kExecLook = 200 * TCS_NS_PER_US;
} // namespace

void on_child(Run &run, Controller &parent, const ::tcs_msg &m, UniqueFd channel)
{
	pid_t pid = (pid_t)m.arg;
	auto refuse = [&](const std::string &why) {
		warn_once(run, "a child of " + parent.name + " runs in real time: " + why);
		if (parent.new_child.pid == pid)
			child_settled(run, parent);
		if (channel) {
			struct tcs_msg w = tcs_msg_make(TCS_MSG_WAKE, m.seq);
			w.arg = -EPERM;
			(void)send(channel.get(), &w, sizeof w, MSG_DONTWAIT | MSG_NOSIGNAL);
		}
	};
	if (!channel)
		return refuse("it sent no channel");
	// Only a child of this controller may register through its channel.
	if (pid_t pp = proc_parent(pid); pp != parent.pid)
		return refuse("pid " + std::to_string(pid) + " is not its child (its parent is " + std::to_string(pp) +
			      ", not " + std::to_string(parent.pid) + ")");
	for (auto &o : run.ctls)
		if (o->pid == pid && o->state() != CtlState::Exited)
			return refuse("pid " + std::to_string(pid) + " is registered already");
	ControllerSpec spec;
	spec.cpu_scale = parent.scale;
	spec.report_misses = run.trace.is_open();
	spec.random_key = parent.next_child_random_key();
	auto made = Controller::adopt((int)run.ctls.size() + 1, parent, pid, std::move(channel), spec, run.cfg.mode,
				      run.clocks, run.rt, run.devices.bound());
	if (!made)
		return; // its channel is closed: the child sees it and runs in real time
	Controller &c = **made;
	// It starts where its parent was at the fork (or is now, if it does not
	// know), never behind the world. A parent waiting for this very child
	// (its request restarted its slice) is exactly at parent.v(); one still
	// running is settled by that request when it comes (on_forked).
	// Still running, its request's claim bounds where it is: past it, what
	// its CPU clock counts is the hook's (a child that had run before the
	// request came, at the parent's clock as it registered, began 26 us
	// ahead of the parent's time, under load).
	int64_t parent_v = parent.v();
	if (parent.state() == CtlState::Running && run.cfg.mode == TCS_MODE_CPU && parent.new_child.pid != pid) {
		int64_t cpu = parent.cpu_now(), claim = parent.fork_claim();
		if (claim >= 0)
			cpu = std::min(cpu, claim);
		parent_v = std::max(parent_v, parent.v_at_cpu(cpu));
	}
	place_at(c, std::max((m.flags & TCS_CHILD_V_KNOWN) ? m.v : parent_v, run.sim_ns));
	serve_request(c, m.seq, -1);
	c.wait.asked = c.v();
	block(run, c, { .deadline = c.v() }); // (its first answer: at once)
	c.wait.pass_fd = c.page_fd_for_child.release();
	run.ctls.push_back(std::move(*made));
	Controller *raw = run.ctls.back().get();
	trace_controller(run, *raw);
	if (auto s = run.loop.add(raw->channel.get(), [&run, raw](uint32_t) { on_channel(run, *raw, nullptr); }); !s) {
		run.fatal = s;
		return;
	}
	if (auto s = run.loop.add(raw->pidfd.get(), [&run, raw](uint32_t) { on_pidfd(run, *raw); }); !s)
		run.fatal = s;
	if (parent.new_child.pid == pid)
		child_settled(run, parent);
	// Someone new waits for a core: is one that has it asleep? And a
	// free core is its at once (those running may compute on for ever
	// without a budget: each was alone when it was resumed).
	run.lanes.each_running([&run](Controller &r) { arm_watchdog(run, r); });
	schedule(run);
}

// The parent, right after its fork: it waits until its child has
// registered (or died first).
void on_forked(Run &run, Controller &c, const ::tcs_msg &m)
{
	restart_slice(run, c, m.cpu);
	pid_t pid = (pid_t)m.arg;
	for (auto &o : run.ctls)
		if (o->pid == pid && o->parent_id == c.id) {
			// It registered first, while this parent ran on (on a core of
			// its own): at the time of its CPU clock then, which counted
			// the parent's hooks too. Not yet run, it starts here instead,
			// where the spawn's request put its parent.
			if (o->slices == 0 && o->state() == CtlState::Blocked && o->wait.deadline == o->v() && o->v() > c.v()) {
				place_at(*o, std::max(c.v(), run.sim_ns));
				o->wait.deadline = o->v();
			}
			reply_now(run, c, 0);
			return;
		}
	UniqueFd fd((int)syscall(SYS_pidfd_open, pid, 0));
	if (!fd || proc_parent(pid) != c.pid) {
		reply_now(run, c, -ESRCH);
		return;
	}
	// Started by vfork or posix_spawn, it has exec'd already: a program
	// that will not load the preload never registers (it runs in real
	// time, said once when its parent waits for it).
	WillLoad will = proc_will_load(pid, "libtcs_preload");
	if (will == WillLoad::No) {
		reply_now(run, c, 0);
		return;
	}
	c.new_child.pid = pid;
	c.new_child.seq = m.seq;
	c.new_child.fd = c.wait.fd;
	c.new_child.since = wall_now();
	c.new_child.exec = will == WillLoad::Unknown;
	if (c.new_child.exec)
		run.exec_timer.arm(kExecLook, kExecLook);
	c.new_child.pidfd = std::move(fd);
	Controller *raw = &c;
	if (auto s = run.loop.add(c.new_child.pidfd.get(), [&run, raw](uint32_t) { child_settled(run, *raw); }); !s)
		run.fatal = s;
}

// Children whose exec was still under way when their parent asked: looked
// at until they can be seen to load the preload or not.
void on_exec_look(Run &run)
{
	run.exec_timer.consume();
	bool again = false;
	for (auto &c : run.ctls) {
		if (c->new_child.pid == 0 || !c->new_child.exec)
			continue;
		WillLoad will = proc_will_load(c->new_child.pid, "libtcs_preload");
		c->new_child.exec = will == WillLoad::Unknown;
		if (will == WillLoad::No)
			child_settled(run, *c);
		again = again || c->new_child.exec;
	}
	if (!again)
		run.exec_timer.disarm();
}

void child_settled(Run &run, Controller &parent)
{
	if (parent.new_child.pid == 0)
		return;
	run.loop.remove(parent.new_child.pidfd.get());
	parent.new_child.pidfd.reset();
	parent.new_child.pid = 0;
	if (parent.state() == CtlState::Exited)
		return;
	// The answer goes to the request that asked (a thread's request since
	// has taken the controller's record of the last one); another thread's
	// wait that is the controller's own now keeps its record.
	const bool aside = set_own_wait_aside(run, parent, parent.new_child.fd >= 0 ? parent.new_child.fd : parent.channel.get());
	serve_request(parent, parent.new_child.seq, parent.new_child.fd);
	reply_now(run, parent, 0);
	if (aside)
		schedule(run);
}

// Whether c has a child that runs in real time, outside tcs: a static
// program, or one whose environment lost LD_PRELOAD, started with vfork or
// posix_spawn (it would register when its program loads). A wait for a
// child then passes in real time, as that child's time does: each step is
// a re-check. Said once per child, once it has gone unregistered for long
// enough not to be one still loading.
bool has_real_time_child(Run &run, Controller &c)
{
	bool any = false;
	int64_t now = wall_now();
	for (const auto &o : run.ctls)
		if (o->parent_id == c.id && o->runs_unhooked && o->state() != CtlState::Exited)
			any = true;
	for (pid_t child : proc_children(c.pid)) {
		if (std::any_of(run.ctls.begin(), run.ctls.end(), [child](const auto &o) { return o->pid == child; }))
			continue;
		any = true;
		auto [it, fresh] = c.unregistered_children.try_emplace(child, now);
		if (!fresh && it->second >= 0 && now - it->second > kRegistrationGrace) {
			it->second = -1; // said
			warn_once(run, "process " + std::to_string(child) + " (" + proc_name(child, "?") + "), started by " + c.name +
				  ", runs in real time: it did not load tcs's preload (a static program, or LD_PRELOAD removed "
				  "from its environment)");
		}
	}
	return any;
}

// A wait for a child's end begins (side: a thread's, else the
// controller's own). With a child in real time, the wait's own time-out
// does not count: the child's end does, in real time, looked for at each
// step (if nothing else has a next event, virtual time passes at the speed
// of real time meanwhile). After a child ended unseen (the program looked
// for it just before, and the exit came between its look and its wait), it
// re-checks at once, at the child's end if that is later (what it finds
// then must not have ended in its future).
void child_wait_begins(Run &run, Controller &c, const ::tcs_msg &m, Request *side)
{
	if (!(m.flags & TCS_BLOCK_CHILD))
		return;
	if (has_real_time_child(run, c)) {
		if (side) {
			side->flags |= TCS_BLOCK_RECHECK;
		} else {
			c.wait.recheck = true;
			c.wait.deadline = TCS_NEVER;
		}
	}
	if (!c.child_ended)
		return;
	c.child_ended = false;
	if (side)
		side->reason = TCS_WAKE_RECHECK;
	else
		wake(run, c, std::max(c.v(), c.child_ended_at), TCS_WAKE_RECHECK);
}

} // namespace tcs
