// A controller's end: its pidfd readable (all its threads gone, or only
// its main one), its exit accounted (its CPU to the last), or tcs dropping
// it for what it sent.
#include "exits.h"
#include "record_replay.h"

#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>

#include <algorithm>
#include <cstring>

#include "clock_ns.h"
#include "proc_info.h"
#include "remote.h"
#include "serve.h"
#include "slices.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"
#include "threads.h"
#include "waits.h"
#include "world_steps.h"
#include "transitions.h"

namespace tcs {

// The CPU clock of a controller that has just ended, read at normal
// priority: the kernel's sum over its threads waits for a thread still on
// its way out, which our wake-up may have preempted on our core, and at
// SCHED_FIFO it would never get to finish.
int64_t exited_cpu(Run &run, const Controller &c)
{
	coordinator_fifo(run.rt, false);
	int64_t cpu = c.cpu_now();
	coordinator_fifo(run.rt, true);
	return cpu;
}

void on_pidfd(Run &run, Controller &c)
{
	if (c.state() == CtlState::Exited)
		return;
	if (c.parent_id != 0) {
		// A child of a controller: its parent reaps it, not us. Its pidfd
		// being readable says it has ended; its zombie (if the parent has
		// not reaped it yet) still tells its CPU and exit status.
		int64_t cpu = exited_cpu(run, c);
		if (cpu > 0)
			c.account(cpu, run.cfg.mode);
		if (c.lane >= 0)
			trace_slice_end(run, c, "exited", std::max<int64_t>(cpu, 0));
		on_exit(run, c, proc_exit_status(c.pid));
		return;
	}
	siginfo_t si = {};
	// Peek first: a zombie's CPU clock still reads, so its last slice counts.
	if (waitid(P_PIDFD, (id_t)c.pidfd.get(), &si, WEXITED | WNOHANG | WNOWAIT) < 0)
		return;
	// Its main thread has ended, not yet all of it: look again soon.
	auto later = [&] {
		run.loop.remove(c.pidfd.get());
		if (std::find(run.exiting.begin(), run.exiting.end(), &c) == run.exiting.end())
			run.exiting.push_back(&c);
		run.exit_timer.arm(100 * TCS_NS_PER_US);
	};
	if (si.si_pid == 0)
		return later();
	int64_t cpu = exited_cpu(run, c);
	c.account(cpu, run.cfg.mode);
	replay_exit(run, c);
	if (c.lane >= 0)
		trace_slice_end(run, c, "exited", cpu);
	si = {};
	if (waitid(P_PIDFD, (id_t)c.pidfd.get(), &si, WEXITED | WNOHANG) < 0)
		return;
	if (si.si_pid == 0)
		return later();
	int status = si.si_code == CLD_EXITED ? W_EXITCODE(si.si_status, 0) : si.si_status & 0x7f;
	if (si.si_code == CLD_DUMPED)
		status |= WCOREFLAG;
	on_exit(run, c, status);
}

void on_exit(Run &run, Controller &c, int wait_status)
{
	run.devices.take_lazy_commands(c, -1, run.trace); // its last commands count
	journal_ends(run, c);
	move(run, c, CtlMove::Exit);
	c.exit_status = wait_status;
	// A parent waiting for its children learns of it at the child's
	// virtual time; one waiting for something else was sent SIGCHLD then
	// (a handler of it may end its wait, as in coreutils timeout).
	for (auto &p : run.ctls) {
		if (p->id != c.parent_id)
			continue;
		bool seen = false;
		for (Request &w : p->side_waits)
			if (w.flags & TCS_BLOCK_CHILD) {
				w.reason = TCS_WAKE_RECHECK;
				seen = true;
			}
		// A thread of a running parent waits for it: answered now, at the
		// parent's time now (its other threads may compute on without a
		// budget: nothing else would come to end the wait).
		if (seen && p->state() == CtlState::Running) {
			if (run.cfg.mode == TCS_MODE_CPU)
				p->account(p->cpu_now(), run.cfg.mode);
			end_side_waits(run, *p);
		}
		if (p->state() == CtlState::Blocked && p->wait.for_child && !p->sync) {
			wake(run, *p, std::max(p->v(), c.v()), TCS_WAKE_RECHECK);
			seen = true;
		} else if (waiting(p->state())) {
			p->note_signal(std::max(p->v(), c.v()));
		}
		// Not waiting for it now: its next wait for a child re-checks,
		// no earlier than the child's end.
		p->child_ended = !seen;
		if (!seen)
			p->child_ended_at = std::max(p->child_ended_at, c.v());
	}
	run.loop.remove(c.channel.get());
	for (auto &t : c.threads)
		run.loop.remove(t->fd.get());
	c.threads.clear();
	c.side_waits.clear();
	run.loop.remove(c.pidfd.get());
	run.lanes.leave(c);
	c.ended_by_tcs = run.ending;
	if (c.parent_id == 0 && run.cfg.serve) {
		// Served: its children go with it, as they do at the end of a run.
		for (auto &o : run.ctls)
			if (o->state() != CtlState::Exited && descends_from(run, *o, c.id))
				kill(o->pid, SIGKILL);
		if (run.cfg.on_controller_end)
			run.cfg.on_controller_end(report_of(run, c));
		word_of_controllers(run);
	}
	if (run.cfg.serve)
		c.release(); // served for long: its fds and memory go back now
	schedule(run);
}

void drop(Run &run, Controller &c, const std::string &why)
{
	c.dropped = why;
	c.mailbox.attach(nullptr); // nothing more of it is looked at
	kill(c.pid, SIGKILL);
	// Its pidfd reports the death; until then it must not be scheduled.
	run.lanes.leave(c);
	run.loop.remove(c.channel.get());
	for (auto &t : c.threads)
		run.loop.remove(t->fd.get());
	c.threads.clear();
	c.side_waits.clear();
	move(run, c, CtlMove::Drop); // (never scheduled again: what it waited in is moot)
	c.sync.reset();
	schedule(run);
}

} // namespace tcs
