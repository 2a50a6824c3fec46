// Serving (coordinatord): controllers that attach to a running world and
// leave it, a world held until those it expects are there, and the fds of
// the daemon's socket and clients in the run's one event loop.
#include "serve.h"

#include <signal.h>

#include <algorithm>

#include "remote.h"
#include "slices.h"
#include "world_steps.h"

namespace tcs {

Result<AttachedController> attach(Run &run, const ControllerSpec &spec)
{
	if (run.ending)
		return Error{ "the world is shutting down" };
	if (auto s = add_controller(run, spec); !s)
		return s.error();
	Controller &c = *run.ctls.back();
	// It joins the world where it is: virtual time never runs ahead of it
	// from here, since it is behind the next step until it has run.
	place_at(c, run.sim_ns);
	run.idle_timer.disarm();
	word_of_controllers(run);
	schedule(run);
	return AttachedController{ c.id, c.pid };
}

void hold_world(Run &run, bool on)
{
	run.world_held = on;
	if (!on) {
		grant_now(run); // agents start with the world
		schedule(run);
	}
}

Controller *top_level(Run &run, int id)
{
	if (id < 1 || id > (int)run.ctls.size() || run.ctls[id - 1]->parent_id != 0)
		return nullptr;
	return run.ctls[id - 1].get();
}

// Controllers are numbered from 1 in the order they came, and never leave
// run.ctls: a parent's id finds it.
bool descends_from(const Run &run, const Controller &o, int root)
{
	for (int p = o.parent_id; p > 0 && p <= (int)run.ctls.size(); p = run.ctls[p - 1]->parent_id)
		if (p == root)
			return true;
	return false;
}

void signal_controller(Run &run, int id, int signo)
{
	Controller *c = top_level(run, id);
	if (!c || c->state() == CtlState::Exited)
		return;
	kill(c->pid, signo);
	// A stopped one gets it when it next runs; a waiting one is looked at
	// now, where the world is (its handler may end its wait).
	if (waiting(c->state()))
		c->note_signal(std::max(c->v(), run.sim_ns));
	schedule(run);
}

void end_controller(Run &run, int id)
{
	Controller *c = top_level(run, id);
	if (!c || c->state() == CtlState::Exited)
		return;
	// One that has not begun (held before its exec) has nothing to tidy.
	if (!c->attached && c->stopped) {
		kill(c->pid, SIGKILL);
		return;
	}
	c->kill_after = wall_now() + kEndGrace;
	signal_controller(run, id, SIGTERM);
}

Status watch(Run &run, int fd, std::function<void()> on_ready)
{
	return run.loop.add(fd, [f = std::move(on_ready)](uint32_t) { f(); });
}

void unwatch(Run &run, int fd)
{
	run.loop.remove(fd);
}

} // namespace tcs
