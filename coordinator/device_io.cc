// Virtual device I/O (docs/DESIGN.md §2, §4): causality and zero-order hold.
// A sensor record due at T carries the world at the last step boundary
// <= T; it is made when the world reaches that boundary and put into the
// controller's fd when the controller's virtual time reaches T. A command
// written at V is held from the first boundary >= V. A controller asking
// for what the world has not computed yet waits for it.
#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>

#include <linux/sockios.h>

#include "coordinator.h"
#include "tcs/protocol.h"

namespace tcs {

namespace {
// Records made but never read: a real sensor's buffer overflows too.
constexpr size_t kMaxQueued = 4096;
// Opens per controller (a controller is untrusted: no unbounded growth).
constexpr size_t kMaxOpens = 1024;
} // namespace

Status Coordinator::bind_devices()
{
	for (const auto &cfg : cfg_.devices) {
		BoundDevice d;
		d.cfg = cfg;
		if (!world_)
			return Error{ cfg.path + ": a device needs a world with signals" };
		for (const auto &name : cfg.signals) {
			long i = world_->find(name);
			if (i < 0)
				return Error{ cfg.path + ": unknown signal '" + name + "'" };
			const tcs_sim_signal_info &info = world_->signal((size_t)i);
			if (cfg.kind == TCS_DEVICE_ACTUATOR && !(info.flags & TCS_SIM_SIGNAL_WRITABLE))
				return Error{ cfg.path + ": signal '" + name + "' cannot be commanded" };
			d.signals.push_back((size_t)i);
			d.width += info.width;
		}
		d.command.assign(d.width, 0.0);
		devices_.push_back(std::move(d));
	}
	return Ok{};
}

void Coordinator::reply_now(Controller &c, int64_t arg)
{
	c.wake_arg = arg;
	c.wake_reason = TCS_WAKE_DEADLINE;
	send_wake(c);
}

// A request answered while the controller's slice goes on: the hook's cost
// from the request on must not be charged, so the slice restarts at the
// request (its budget less what it has used), as after any wait.
void Coordinator::restart_slice(Controller &c, int64_t request_cpu)
{
	if (c.state != CtlState::Running)
		return;
	int64_t at = charge_point(c, request_cpu);
	int64_t used = c.slice_cpu(at);
	c.account(at, cfg_.mode);
	c.publish_slice(at);
	c.slice_wall = wall_now();
	c.budget = std::max<int64_t>(c.budget - used, 1);
	c.checked_used = 0;
}

void Coordinator::on_dev_open(Controller &c, const ::tcs_msg &m)
{
	restart_slice(c, m.cpu);
	c.wait.seq = m.seq;
	if ((size_t)m.arg >= devices_.size()) {
		reply_now(c, -ENOENT);
		return;
	}
	// A slot whose fd the controller has closed is free again.
	size_t slot = c.devices.size();
	for (size_t i = 0; i < c.devices.size(); i++) {
		struct pollfd p = { c.devices[i]->sock.get(), POLLRDHUP, 0 };
		if (c.devices[i]->gone || (poll(&p, 1, 0) == 1 && (p.revents & (POLLHUP | POLLRDHUP)))) {
			slot = i;
			break;
		}
	}
	if (slot == kMaxOpens) {
		reply_now(c, -EMFILE);
		return;
	}
	BoundDevice &dev = devices_[(size_t)m.arg];
	bool reads = m.flags & TCS_DEV_READ, writes = m.flags & TCS_DEV_WRITE;
	if ((dev.cfg.kind == TCS_DEVICE_SENSOR && writes) || (dev.cfg.kind == TCS_DEVICE_ACTUATOR && reads)) {
		reply_now(c, -EACCES);
		return;
	}
	int sv[2];
	if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) < 0) {
		reply_now(c, -errno);
		return;
	}
	auto d = std::make_unique<OpenDevice>();
	d->dev = &dev;
	d->sock.reset(sv[0]);
	int fl = fcntl(sv[0], F_GETFL);
	fcntl(sv[0], F_SETFL, fl | O_NONBLOCK);
	if (dev.cfg.kind == TCS_DEVICE_SENSOR && !dev.cfg.latest && dev.cfg.period_ns > 0) {
		// A stream runs at its rate from the start of the run, whoever reads.
		d->next_due = (std::max(c.v, sim_ns_) + dev.cfg.period_ns - 1) / dev.cfg.period_ns * dev.cfg.period_ns;
		make_records(*d, sim_ns_ + cfg_.step_ns);
	}
	if (slot == c.devices.size())
		c.devices.push_back(std::move(d));
	else
		c.devices[slot] = std::move(d);
	c.wake_fd = sv[1];
	reply_now(c, (int64_t)slot);
}

void Coordinator::make_records(OpenDevice &d, int64_t until)
{
	const BoundDevice &dev = *d.dev;
	if (!world_ || dev.cfg.kind != TCS_DEVICE_SENSOR || dev.cfg.latest || dev.cfg.period_ns <= 0)
		return;
	std::vector<double> values;
	for (size_t i : dev.signals)
		world_->read(i, values);
	std::string record = format_record(dev.cfg.format, values);
	for (; d.next_due < until; d.next_due += dev.cfg.period_ns) {
		if (d.queue.size() == kMaxQueued) {
			d.queue.pop_front();
			if (d.dropped++ == 0)
				warn_once(dev.cfg.path + ": more than " + std::to_string(kMaxQueued) +
					  " records unread: the oldest are dropped");
		}
		d.queue.emplace_back(d.next_due, record);
	}
}

void Coordinator::fill_streams(int64_t until)
{
	for (auto &c : ctls_)
		for (auto &d : c->devices)
			if (!d->gone)
				make_records(*d, until);
}

// A record goes into an fd only once the controller has read all that the
// fd held: so a reader that stalls keeps at most what it had then, and the
// records waiting here, kMaxQueued at most, lose their oldest first. (Filled
// whenever there was room, the fd's buffer would keep hundreds of the oldest
// records and the drops would cut out the middle.)
static bool drained(const OpenDevice &d)
{
	int unread = 0;
	return ioctl(d.sock.get(), SIOCOUTQ, &unread) == 0 && unread == 0;
}

void Coordinator::deliver(Controller &c)
{
	for (auto &d : c.devices) {
		if (d->gone || d->queue.empty() || d->queue.front().first > c.v || !drained(*d))
			continue;
		while (!d->gone && !d->queue.empty() && d->queue.front().first <= c.v) {
			const std::string &rec = d->queue.front().second;
			ssize_t n = send(d->sock.get(), rec.data(), rec.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
			if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
				break; // its buffer is full: it keeps the rest until it reads
			if (n < 0) {
				d->gone = true; // closed by the controller
				d->queue.clear();
				break;
			}
			if ((size_t)n < rec.size()) {
				d->queue.front().second.erase(0, (size_t)n);
				break;
			}
			d->queue.pop_front();
		}
	}
}

int64_t Coordinator::next_record_due(const Controller &c) const
{
	int64_t due = TCS_NEVER;
	for (const auto &d : c.devices) {
		if (d->gone || d->dev->cfg.kind != TCS_DEVICE_SENSOR || d->dev->cfg.latest)
			continue;
		due = std::min(due, d->queue.empty() ? d->next_due : d->queue.front().first);
	}
	return due;
}

bool Coordinator::take_commands(Controller &c, OpenDevice &d, bool written_lazily)
{
	char buf[4096];
	ssize_t n;
	// A short read has emptied the socket: the writer is not running.
	do {
		n = recv(d.sock.get(), buf, sizeof buf, MSG_DONTWAIT);
		if (n > 0)
			d.input.append(buf, (size_t)n);
	} while (n == (ssize_t)sizeof buf);
	BoundDevice &dev = *d.dev;
	std::vector<std::vector<double>> records;
	std::string why;
	bool ok = parse_records(dev.cfg.format, dev.width, d.input, records, &why);
	for (auto &values : records) {
		if (dev.cfg.limit)
			for (double &v : values)
				v = std::clamp(v, -*dev.cfg.limit, *dev.cfg.limit);
		if (trace_.is_open())
			trace_.command(c.id, dev.cfg.path, c.v, values, false);
		commands_.emplace_back(c.v, &dev, std::move(values));
	}
	if (!ok) {
		if (trace_.is_open())
			trace_.command(c.id, dev.cfg.path, c.v, {}, true);
		dev.malformed++;
		// The preload vouched for a lazy write's records: only a write
		// around its hooks (a raw system call) can get here.
		warn_once(c.name + ": " + dev.cfg.path + ": malformed record (" + why + "): " +
			  (written_lazily ? "written around tcs's hooks, it is dropped"
					  : "the write fails with EINVAL") +
			  " and the last valid command stays in force");
	}
	return ok;
}

void Coordinator::take_lazy_commands(Controller &c, int64_t except)
{
	for (uint64_t bits = c.take_lazy_handles(); bits != 0; bits &= bits - 1) {
		size_t h = (size_t)__builtin_ctzll(bits);
		if ((int64_t)h != except && h < c.devices.size() && c.devices[h]->dev->cfg.kind == TCS_DEVICE_ACTUATOR)
			take_commands(c, *c.devices[h], true);
	}
}

void Coordinator::apply_commands(int64_t boundary)
{
	// In the order they were written; the last one before the boundary wins.
	while (!commands_.empty() && std::get<0>(commands_.front()) <= boundary) {
		auto &[at, dev, values] = commands_.front();
		dev->command = values;
		size_t off = 0;
		for (size_t i : dev->signals) {
			world_->write(i, dev->command.data() + off);
			off += world_->signal(i).width;
		}
		commands_.pop_front();
	}
	// Agents' commands (agents.cc checked them), in the order written.
	agents_.apply(*world_, boundary);
}

Status Coordinator::step_world()
{
	if (world_) {
		apply_commands(sim_ns_);
		if (auto s = world_->step(); !s)
			return s;
		step_walls_.add(world_->last_step_wall_ns());
		if (trace_.is_open()) {
			std::vector<double> joints;
			joints.reserve(joint_signals_.size());
			for (size_t i : joint_signals_)
				world_->read(i, joints);
			trace_.step(sim_ns_ + cfg_.step_ns, wall_now() - wall_start_, world_->last_step_wall_ns(),
				    std::move(joints));
		}
		if (cfg_.on_step)
			cfg_.on_step(sim_ns_ + cfg_.step_ns, *world_);
	}
	sim_ns_ += cfg_.step_ns;
	steps_++;
	fill_streams(sim_ns_ + cfg_.step_ns);
	grant_now();
	return Ok{};
}

void Coordinator::on_dev_sync(Controller &c, const ::tcs_msg &m)
{
	if (c.state == CtlState::Blocked) {
		drop(c, "it made a device request while waiting");
		return;
	}
	restart_slice(c, m.cpu);
	c.wait.seq = m.seq;
	c.wake_arg = 0;
	if (m.kind != TCS_SYNC_POLL && (m.arg < 0 || (size_t)m.arg >= c.devices.size())) {
		reply_now(c, -EBADF);
		return;
	}
	if (m.kind == TCS_SYNC_WRITE) {
		OpenDevice &d = *c.devices[(size_t)m.arg];
		if (d.dev->cfg.kind == TCS_DEVICE_ACTUATOR && !take_commands(c, d, false))
			c.wake_arg = -EINVAL;
		reply_now(c, c.wake_arg);
		return;
	}
	c.sync_pending = true;
	c.sync_kind = m.kind;
	c.sync_handle = m.arg;
	c.sync_nonblock = m.flags & TCS_DEV_NONBLOCK;
	if (!ending_ && c.v >= sim_ns_ + cfg_.step_ns) {
		// It is ahead of the world: it waits until the world catches up.
		if (c.lane >= 0) {
			lanes_.leave(c);
			trace_slice_end(c, "blocked", c.cpu_now());
		}
		c.state = CtlState::Ready;
		schedule();
		return;
	}
	bool was_running = c.state == CtlState::Running;
	if (complete_sync(c)) {
		c.wake_pending = false;
		send_wake(c);
		return;
	}
	// A blocking read with nothing due: it waits for the next record.
	if (was_running && c.lane >= 0) {
		lanes_.leave(c);
		trace_slice_end(c, "blocked", c.cpu_now());
	}
	schedule();
}

// The world is at or past the controller's step: do what it asked. False
// when it must wait for the next record (then it is Blocked until then).
bool Coordinator::complete_sync(Controller &c)
{
	deliver(c);
	c.sync_pending = false;
	c.wake_arg = 0;
	if (c.sync_kind != TCS_SYNC_READ) {
		c.wake_pending = true;
		return true;
	}
	OpenDevice &d = *c.devices[(size_t)c.sync_handle];
	if (!drained(d) || d.gone) {
		c.wake_pending = true;
		return true;
	}
	// A 'latest' sensor answers with the world now; so does a stream once
	// the run is ending (the world has stopped; its last state stands).
	if ((d.dev->cfg.latest || (ending_ && d.queue.empty())) && world_) {
		std::vector<double> values;
		for (size_t i : d.dev->signals)
			world_->read(i, values);
		std::string rec = format_record(d.dev->cfg.format, values);
		(void)!send(d.sock.get(), rec.data(), rec.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
		c.wake_pending = true;
		return true;
	}
	if (c.sync_nonblock || next_record_due(c) == TCS_NEVER) {
		c.wake_arg = c.sync_nonblock ? -EAGAIN : 0;
		c.wake_pending = true;
		return true;
	}
	c.sync_pending = true;
	c.state = CtlState::Blocked;
	c.wait.deadline = d.queue.empty() ? d.next_due : d.queue.front().first;
	c.wait.recheck = false;
	c.wait.devices = false;
	c.wake_pending = false;
	return false;
}

} // namespace tcs
