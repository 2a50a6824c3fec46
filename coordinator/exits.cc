// A controller's end: its pidfd readable (all its threads gone, or only
// its main one), its exit accounted (its CPU to the last), or tcs dropping
// it for what it sent.
#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>

#include <algorithm>
#include <cstring>

#include "clock_ns.h"
#include "coordinator.h"
#include "proc_info.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"

namespace tcs {

// The CPU clock of a controller that has just ended. The kernel's sum over
// its threads waits for a thread still on its way out, which our wake-up
// may have preempted on our core: at SCHED_FIFO we would spin in that
// clock_gettime forever (seen with every multi-threaded controller), so we
// step down to let it finish.
int64_t Coordinator::exited_cpu(const Controller &c)
{
	coordinator_fifo(rt_, false);
	int64_t cpu = c.cpu_now();
	coordinator_fifo(rt_, true);
	return cpu;
}

void Coordinator::on_pidfd(Controller &c)
{
	if (c.state == CtlState::Exited)
		return;
	if (c.parent_id != 0) {
		// A child of a controller: its parent reaps it, not us. Its pidfd
		// being readable says it has ended; its zombie (if the parent has
		// not reaped it yet) still tells its CPU and exit status.
		int64_t cpu = exited_cpu(c);
		if (cpu > 0)
			c.account(cpu, cfg_.mode);
		if (c.lane >= 0)
			trace_slice_end(c, "exited", std::max<int64_t>(cpu, 0));
		on_exit(c, proc_exit_status(c.pid));
		return;
	}
	siginfo_t si = {};
	// Peek first: a zombie's CPU clock still reads, so its last slice counts.
	if (waitid(P_PIDFD, (id_t)c.pidfd.get(), &si, WEXITED | WNOHANG | WNOWAIT) < 0)
		return;
	// Its main thread has ended, not yet all of it: look again soon.
	auto later = [&] {
		loop_.remove(c.pidfd.get());
		if (std::find(exiting_.begin(), exiting_.end(), &c) == exiting_.end())
			exiting_.push_back(&c);
		exit_timer_.arm(100 * TCS_NS_PER_US);
	};
	if (si.si_pid == 0)
		return later();
	int64_t cpu = exited_cpu(c);
	c.account(cpu, cfg_.mode);
	if (c.lane >= 0)
		trace_slice_end(c, "exited", cpu);
	si = {};
	if (waitid(P_PIDFD, (id_t)c.pidfd.get(), &si, WEXITED | WNOHANG) < 0)
		return;
	if (si.si_pid == 0)
		return later();
	int status = si.si_code == CLD_EXITED ? W_EXITCODE(si.si_status, 0) : si.si_status & 0x7f;
	if (si.si_code == CLD_DUMPED)
		status |= WCOREFLAG;
	on_exit(c, status);
}

void Coordinator::on_exit(Controller &c, int wait_status)
{
	devices_.take_lazy_commands(c, -1, trace_); // its last commands count
	c.state = CtlState::Exited;
	c.exit_status = wait_status;
	// A parent waiting for its children learns of it at the child's
	// virtual time; one waiting for something else was sent SIGCHLD then
	// (a handler of it may end its wait, as in coreutils timeout).
	for (auto &p : ctls_) {
		if (p->id != c.parent_id)
			continue;
		bool seen = false;
		for (SideWait &w : p->side)
			if (w.flags & TCS_BLOCK_CHILD) {
				w.wake_reason = TCS_WAKE_RECHECK;
				seen = true;
			}
		if (p->state == CtlState::Blocked && p->wait.for_child && !p->sync_pending) {
			wake(*p, std::max(p->v, c.v), TCS_WAKE_RECHECK);
			seen = true;
		} else if (p->state == CtlState::Blocked) {
			p->kick(std::max(p->v, c.v));
		}
		// Not waiting for it now: its next wait for a child re-checks.
		p->child_ended = !seen;
	}
	loop_.remove(c.channel.get());
	for (auto &t : c.threads)
		loop_.remove(t->fd.get());
	c.threads.clear();
	c.side.clear();
	loop_.remove(c.pidfd.get());
	lanes_.leave(c);
	c.ended_by_tcs = ending_;
	if (c.parent_id == 0 && cfg_.serve) {
		// Served: its children go with it, as they do at the end of a run.
		for (auto &o : ctls_)
			if (o->state != CtlState::Exited && descends_from(*o, c.id))
				kill(o->pid, SIGKILL);
		if (cfg_.on_controller_end)
			cfg_.on_controller_end(report_of(c));
		word_of_controllers();
	}
	if (cfg_.serve)
		c.release(); // served for long: its fds and memory go back now
	schedule();
}

void Coordinator::drop(Controller &c, const std::string &why)
{
	c.dropped = why;
	c.mailbox.attach(nullptr); // nothing more of it is looked at
	kill(c.pid, SIGKILL);
	// Its pidfd reports the death; until then it must not be scheduled.
	lanes_.leave(c);
	loop_.remove(c.channel.get());
	for (auto &t : c.threads)
		loop_.remove(t->fd.get());
	c.threads.clear();
	c.side.clear();
	c.state = CtlState::Blocked;
	c.wait.deadline = TCS_NEVER;
	c.wait.recheck = false;
	c.wait.devices = false;
	c.sync_pending = false;
	c.wake_pending = false;
	schedule();
}

} // namespace tcs
