// coordinatord's clients: attach requests in, STARTED/ENDED out.
#include "clients.h"

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>

#include "attach_socket.h"

namespace tcs {

namespace {

std::string basename_of(const std::string &path)
{
	size_t slash = path.find_last_of('/');
	return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Replies are small and the client waits for them: a client that cannot
// take one is broken, and loses it rather than stall the world.
void reply(int fd, AttachType type, const std::string &payload)
{
	std::string frame = encode_frame(type, payload);
	(void)send(fd, frame.data(), frame.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
}

} // namespace

Clients::Clients(Coordinator &co, const Scenario &scenario, Log log) : co_(co), log_(std::move(log))
{
	for (const auto &entry : scenario.controllers)
		expected_.push_back(Expected{ basename_of(entry.argv[0]), entry.cpu_scale, false });
	held_ = !expected_.empty();
	co_.hold(held_);
}

Clients::~Clients()
{
	for (auto &c : clients_)
		co_.unwatch(c->fd.get());
	if (listening_)
		co_.unwatch(listening_.get());
}

Status Clients::serve(UniqueFd listening)
{
	listening_ = std::move(listening);
	return co_.watch(listening_.get(), [this] { on_accept(); });
}

std::string Clients::waiting_for() const
{
	std::string names;
	for (const auto &e : expected_)
		if (!e.attached)
			names += (names.empty() ? "" : ", ") + e.program;
	return names;
}

void Clients::on_accept()
{
	UniqueFd fd(accept4(listening_.get(), nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK));
	if (!fd)
		return; // EAGAIN, or the client gave up already
	auto c = std::make_unique<Client>();
	c->fd = std::move(fd);
	auto uid = peer_uid(c->fd.get());
	if (!uid || *uid != geteuid()) {
		std::string who = uid ? "uid " + std::to_string(*uid) : uid.error().message;
		log_("refused a client (" + who + "): coordinatord serves uid " + std::to_string(geteuid()) + " only");
		reply(c->fd.get(), AttachType::Refused,
		      "coordinatord serves uid " + std::to_string(geteuid()) + " only, not " + who);
		return;
	}
	Client *raw = c.get();
	if (auto s = co_.watch(raw->fd.get(), [this, raw] { on_readable(raw); }); !s) {
		log_("cannot serve a client: " + s.error().message);
		return;
	}
	clients_.push_back(std::move(c));
}

void Clients::on_readable(Client *c)
{
	ssize_t n = recv_some(c->fd.get(), c->in, c->fds, 3);
	if (n < 0 && (errno == EAGAIN || errno == EINTR))
		return;
	if (n <= 0) {
		// Gone: its controller goes with it (SIGTERM, then SIGKILL); the
		// record stays until the controller's end is reported.
		co_.unwatch(c->fd.get());
		c->fd.reset();
		if (c->controller == 0)
			return close_client(c);
		log_(c->name + ": its tcs-run has gone, so it is ended");
		leave_slot(*c);
		co_.end_controller(c->controller);
		return;
	}
	for (;;) {
		auto f = take_frame(c->in);
		if (!f) {
			refuse(*c, f.error().message);
			return close_client(c);
		}
		if (!*f)
			return;
		on_frame(*c, **f);
		if (!c->fd)
			return close_client(c);
	}
}

void Clients::on_frame(Client &c, const AttachFrame &f)
{
	if (f.type == AttachType::Run && c.controller == 0) {
		auto req = decode_run(f.payload);
		if (!req)
			return refuse(c, req.error().message);
		return start(c, std::move(*req));
	}
	if (f.type == AttachType::Signal && c.controller != 0) {
		auto signo = decode_signal(f.payload);
		if (!signo)
			return refuse(c, signo.error().message);
		co_.signal_controller(c.controller, *signo);
		return;
	}
	refuse(c, "unexpected frame");
}

void Clients::start(Client &c, RunRequest req)
{
	if (c.fds.size() != 3)
		return refuse(c, "the run request came without stdin, stdout and stderr");
	ControllerSpec spec;
	spec.path = req.path;
	spec.argv = std::move(req.argv);
	spec.env = std::move(req.env);
	spec.cwd = std::move(req.cwd);
	for (int i = 0; i < 3; i++)
		spec.stdio[i] = c.fds[i].get();
	Expected *e = expected_for(spec.argv[0]);
	spec.cpu_scale = req.cpu_scale > 0 ? req.cpu_scale : e && e->cpu_scale ? *e->cpu_scale : 1.0;
	auto made = co_.attach(spec);
	c.fds.clear(); // the controller has its copies
	if (!made)
		return refuse(c, "cannot start " + spec.argv[0] + ": " + made.error().message);
	c.controller = made->id;
	c.name = spec.argv[0];
	StartedReply r;
	r.id = made->id;
	r.pid = made->pid;
	r.mode = co_.mode();
	r.fifo_cpu = co_.fifo_cpu();
	r.v_start = co_.sim_time();
	reply(c.fd.get(), AttachType::Started, encode_started(r));
	std::string count;
	if (e) {
		e->attached = true;
		c.slot = e;
		size_t n = (size_t)std::count_if(expected_.begin(), expected_.end(), [](auto &x) { return x.attached; });
		count = ", " + std::to_string(n) + " of " + std::to_string(expected_.size()) + " expected";
	}
	log_("attached " + c.name + " (pid " + std::to_string(made->pid) + ")" + count);
	release_if_complete();
}

void Clients::release_if_complete()
{
	if (held_ && waiting_for().empty()) {
		held_ = false;
		log_("every expected controller has attached: the world runs");
		co_.hold(false);
	}
}

void Clients::agent_programs(const std::string &agent, const std::vector<std::string> &programs)
{
	if (!held_)
		return; // the world runs: it waits for nobody now
	std::vector<Expected *> &slots = agent_slots_[agent];
	for (Expected *e : slots)
		e->attached = false;
	slots.clear();
	for (const auto &p : programs)
		if (Expected *e = expected_for(p)) {
			e->attached = true;
			slots.push_back(e);
		}
	size_t n = (size_t)std::count_if(expected_.begin(), expected_.end(), [](auto &x) { return x.attached; });
	log_("agent " + agent + " runs " + std::to_string(programs.size()) + " controller(s); " + std::to_string(n) +
	     " of " + std::to_string(expected_.size()) + " expected");
	release_if_complete();
}

// The scenario's first [[controller]] not yet attached whose program has
// the same name.
Clients::Expected *Clients::expected_for(const std::string &argv0)
{
	std::string name = basename_of(argv0);
	for (auto &e : expected_)
		if (!e.attached && e.program == name)
			return &e;
	return nullptr;
}

void Clients::refuse(Client &c, const std::string &why)
{
	log_("refused a request: " + why);
	reply(c.fd.get(), AttachType::Refused, why);
	if (c.controller != 0)
		co_.end_controller(c.controller);
	co_.unwatch(c.fd.get());
	c.fd.reset();
	c.controller = 0;
}

void Clients::controller_ended(const ControllerReport &r)
{
	for (auto &c : clients_) {
		if (c->controller != r.id)
			continue;
		EndedReply e;
		e.wait_status = r.wait_status;
		e.flags = (r.ended_by_tcs ? kEndedByTcs : 0) | (r.attached ? kEndedAttached : 0);
		e.v_end = r.virtual_ns;
		e.charged_ns = r.charged_ns;
		e.waits = r.waits;
		e.periodic_waits = r.periodic_waits;
		e.deadline_misses = r.deadline_misses;
		e.preemptions = r.preemptions;
		e.dropped = r.dropped;
		if (c->fd)
			reply(c->fd.get(), AttachType::Ended, encode_ended(e));
		log_(c->name + " (controller " + std::to_string(r.id) + ") ended");
		leave_slot(*c);
		c->controller = 0;
		close_client(c.get());
		return;
	}
}

// A controller gone before the world started leaves its [[controller]] to
// be filled again: the world still waits for one.
void Clients::leave_slot(Client &c)
{
	if (held_ && c.slot) {
		c.slot->attached = false;
		log_("the world waits for " + waiting_for() + " again");
	}
	c.slot = nullptr;
}

void Clients::close_client(Client *c)
{
	auto it = std::find_if(clients_.begin(), clients_.end(), [c](auto &p) { return p.get() == c; });
	if (it == clients_.end())
		return;
	if ((*it)->fd)
		co_.unwatch((*it)->fd.get());
	clients_.erase(it);
}

} // namespace tcs
