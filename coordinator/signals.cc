// Signals one controller sends another (kill, killpg, sigqueue, tgkill).
// The kernel delivers them at once, but a waiting receiver only acts on one
// when it gets the core, and while every controller waits the coordinator
// keeps the core to step the world: `timeout 2 sleep 10` would see its
// child die 8 virtual seconds late. So the sender says whom it signalled,
// and each receiver waiting in a hooked wait is woken to re-check at the
// sender's time: it dies there, or runs its handler (its wait ends with
// EINTR), or, if it blocks or ignores the signal, waits on.
//
// A signal to one's own process (pthread_kill, or kill of one's own pid from
// a threaded program) is told after it was sent, and ends the waits of the
// sender's other threads to re-check at its time, at once: the sender runs,
// so time does not pass before the receiver, running its handler, has
// asked for its next wait (which otherwise began when the world next
// stepped: in lockstep up to a whole wait late).
#include "signals.h"

#include <unistd.h>

#include <algorithm>

#include "device_requests.h"
#include "threads.h"

namespace tcs {

namespace {

// Whether kill(target, ...) from a process of group sender_pgid reaches pid.
bool reaches(pid_t pid, int64_t target, pid_t sender_pgid)
{
	if (target > 0)
		return pid == target;
	if (target == -1)
		return true;
	pid_t group = target == 0 ? sender_pgid : (pid_t)-target;
	return group > 0 && getpgid(pid) == group;
}

} // namespace

void on_kill(Run &run, Controller &c, const ::tcs_msg &m)
{
	restart_slice(run, c, m.cpu);
	pid_t sender_pgid = getpgid(c.pid);
	int64_t at = std::max(c.v(), m.v);
	for (auto &o : run.ctls)
		if (o.get() != &c && waiting(o->state()) && reaches(o->pid, m.arg, sender_pgid))
			o->note_signal(at);
	if (!c.side_waits.empty() && reaches(c.pid, m.arg, sender_pgid)) {
		c.recheck_side_waits();
		end_side_waits(run, c);
	}
	reply_now(run, c, 0);
}

} // namespace tcs
