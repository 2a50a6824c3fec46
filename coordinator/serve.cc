// Serving (coordinatord): controllers that attach to a running world and
// leave it, a world held until those it expects are there, and the fds of
// the daemon's socket and clients in the run's one event loop.
#include <signal.h>

#include <algorithm>

#include "coordinator.h"

namespace tcs {

Result<Coordinator::Attached> Coordinator::attach(const ControllerSpec &spec)
{
	if (ending_)
		return Error{ "the world is shutting down" };
	if (auto s = add_controller(spec); !s)
		return s.error();
	Controller &c = *ctls_.back();
	// It joins the world where it is: virtual time never runs ahead of it
	// from here, since it is behind the next step until it has run.
	c.v = sim_ns_;
	idle_timer_.disarm();
	word_of_controllers();
	schedule();
	return Attached{ c.id, c.pid };
}

void Coordinator::hold(bool on)
{
	held_ = on;
	if (!on) {
		grant_now(); // agents start with the world
		schedule();
	}
}

Controller *Coordinator::top_level(int id)
{
	if (id < 1 || id > (int)ctls_.size() || ctls_[id - 1]->parent_id != 0)
		return nullptr;
	return ctls_[id - 1].get();
}

// Controllers are numbered from 1 in the order they came, and never leave
// ctls_: a parent's id finds it.
bool Coordinator::descends_from(const Controller &o, int root) const
{
	for (int p = o.parent_id; p > 0 && p <= (int)ctls_.size(); p = ctls_[p - 1]->parent_id)
		if (p == root)
			return true;
	return false;
}

void Coordinator::signal_controller(int id, int signo)
{
	Controller *c = top_level(id);
	if (!c || c->state == CtlState::Exited)
		return;
	kill(c->pid, signo);
	// A stopped one gets it when it next runs; a waiting one is looked at
	// now, where the world is (its handler may end its wait).
	if (c->state == CtlState::Blocked)
		c->kick(std::max(c->v, sim_ns_));
	schedule();
}

void Coordinator::end_controller(int id)
{
	Controller *c = top_level(id);
	if (!c || c->state == CtlState::Exited)
		return;
	// One that has not begun (held before its exec) has nothing to tidy.
	if (!c->attached && c->stopped) {
		kill(c->pid, SIGKILL);
		return;
	}
	c->kill_after = wall_now() + kEndGrace;
	signal_controller(id, SIGTERM);
}

Status Coordinator::watch(int fd, std::function<void()> on_ready)
{
	return loop_.add(fd, [f = std::move(on_ready)](uint32_t) { f(); });
}

void Coordinator::unwatch(int fd)
{
	loop_.remove(fd);
}

} // namespace tcs
