// What a controller asks of its devices (docs/DESIGN.md §4): an open (DEV_OPEN,
// answered with the socket that is its fd) and a read, write or poll that
// needs the coordinator (DEV_SYNC). A controller asking for what the world
// has not computed yet waits for it. The devices themselves are
// device_server.h's.
#include "device_requests.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>

#include "exits.h"
#include "slices.h"
#include "tcs/protocol.h"
#include "waits.h"
#include "wire_bus.h"
#include "world_steps.h"
#include "transitions.h"

namespace tcs {

namespace {
// Opens per controller (a controller is untrusted: no unbounded growth).
constexpr size_t kMaxOpens = 1024;
} // namespace

void reply_now(Run &run, Controller &c, int64_t arg)
{
	owe_answer(c, TCS_WAKE_DEADLINE, arg);
	answer(run, c);
}

// A request answered while the controller's slice goes on: the hook's cost
// from the request on must not be charged, so the slice restarts at the
// request (its budget less what it has used), as after any wait.
void restart_slice(Run &run, Controller &c, int64_t request_cpu)
{
	c.wait.requested_at = c.v();
	if (c.state() != CtlState::Running)
		return;
	int64_t at = charge_point(run, c, request_cpu);
	int64_t used = c.slice_cpu(at);
	c.account(at, run.cfg.mode);
	c.wait.requested_at = c.v();
	c.publish_slice(at);
	start_slice_clock(run, c);
	c.budget = std::max<int64_t>(c.budget - used, 1);
	c.checked_used = 0;
}

void on_dev_open(Run &run, Controller &c, const ::tcs_msg &m)
{
	restart_slice(run, c, m.cpu);
	if ((size_t)m.arg >= run.devices.bound().size()) {
		reply_now(run, c, -ENOENT);
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
		reply_now(run, c, -EMFILE);
		return;
	}
	BoundDevice &dev = run.devices.bound()[(size_t)m.arg];
	bool reads = m.flags & TCS_DEV_READ, writes = m.flags & TCS_DEV_WRITE;
	if ((dev.cfg.kind == TCS_DEVICE_SENSOR && writes) || (dev.cfg.kind == TCS_DEVICE_ACTUATOR && reads)) {
		reply_now(run, c, -EACCES);
		return;
	}
	WireBus *bus = is_wire(dev.cfg.kind) ? run.wires.bus(dev.cfg.wire) : nullptr;
	if (is_wire(dev.cfg.kind) && !bus) {
		reply_now(run, c, -ENODEV);
		return;
	}
	int sv[2];
	if (socketpair(AF_UNIX, (bus ? bus->socket_type() : SOCK_STREAM) | SOCK_CLOEXEC, 0, sv) < 0) {
		reply_now(run, c, -errno);
		return;
	}
	auto d = std::make_unique<OpenDevice>();
	d->dev = &dev;
	d->sock.reset(sv[0]);
	if (bus) {
		d->wire = run.wires.open(dev.cfg.wire);
		d->wire->kind = dev.cfg.kind;
		d->wire->owner = c.name;
	}
	int fl = fcntl(sv[0], F_GETFL);
	fcntl(sv[0], F_SETFL, fl | O_NONBLOCK);
	if (dev.cfg.kind == TCS_DEVICE_SENSOR && !dev.cfg.latest && dev.cfg.period_ns > 0) {
		// A stream runs at its rate from the start of the run, whoever reads.
		d->next_due = (std::max(c.v(), run.sim_ns) + dev.cfg.period_ns - 1) / dev.cfg.period_ns * dev.cfg.period_ns;
		run.devices.make_records(*d, run.sim_ns + run.cfg.step_ns, run.world.get());
	}
	if (slot == c.devices.size())
		c.devices.push_back(std::move(d));
	else
		c.devices[slot] = std::move(d);
	c.wait.pass_fd = sv[1];
	reply_now(run, c, (int64_t)slot);
}

void on_dev_sync(Run &run, Controller &c, const ::tcs_msg &m)
{
	if (c.state() == CtlState::Blocked) {
		drop(run, c, "it made a device request while waiting");
		return;
	}
	restart_slice(run, c, m.cpu);
	if (m.kind != TCS_SYNC_POLL && (m.arg < 0 || (size_t)m.arg >= c.devices.size())) {
		reply_now(run, c, -EBADF);
		return;
	}
	if (m.kind == TCS_SYNC_WRITE) {
		OpenDevice &d = *c.devices[(size_t)m.arg];
		int64_t result = 0;
		if (d.wire)
			result = run.wires.take(*d.wire, d.sock.get(), c.v(), run.world.get());
		else if (d.dev->cfg.kind == TCS_DEVICE_ACTUATOR && !run.devices.take_commands(c, d, false, run.trace))
			result = -EINVAL;
		reply_now(run, c, result);
		return;
	}
	if ((m.kind == TCS_SYNC_DRAIN || (m.flags & TCS_DEV_DEADLINE)) && !c.devices[(size_t)m.arg]->wire) {
		reply_now(run, c, -EINVAL); // (a wire's alone)
		return;
	}
	c.sync = DeviceSync{ m.kind, m.arg, (m.flags & TCS_DEV_NONBLOCK) != 0,
			     (m.flags & TCS_DEV_DEADLINE) ? m.deadline : TCS_NEVER };
	if (!run.ending && c.v() >= run.sim_ns + run.cfg.step_ns) {
		// It is ahead of the world: it waits until the world catches up.
		if (c.lane >= 0) {
			run.lanes.leave(c);
			trace_slice_end(run, c, "blocked", c.cpu_now());
		}
		move(run, c, CtlMove::Ahead);
		schedule(run);
		return;
	}
	bool was_running = c.state() == CtlState::Running;
	if (complete_sync(run, c)) {
		answer(run, c);
		return;
	}
	// A blocking read with nothing due: it waits for the next record.
	if (was_running && c.lane >= 0) {
		run.lanes.leave(c);
		trace_slice_end(run, c, "blocked", c.cpu_now());
	}
	schedule(run);
}

namespace {
// What a device request comes to once the world has reached it: answered,
// with its result, or waiting until `until` at the latest.
struct SyncOutcome {
	bool answered = true;
	int64_t result = 0;
	int64_t until = TCS_NEVER;
};
SyncOutcome answered(int64_t result = 0)
{
	return { true, result, TCS_NEVER };
}
SyncOutcome waits_until(int64_t until)
{
	return { false, 0, until };
}
} // namespace

// tcdrain(): done once what it wrote has left on the wire.
static SyncOutcome drain(Run &run, Controller &c, const DeviceSync &sync)
{
	OpenDevice &d = *c.devices[(size_t)sync.handle];
	const int64_t at = d.wire && d.wire->bus ? d.wire->bus->drained_at(*d.wire) : 0;
	return at > c.v() && !run.ending ? waits_until(at) : answered();
}

// A wire's read: done when something is in its fd, or it may not wait, or
// its deadline has come (it reads nothing then); else it waits for the next
// arrival, or the wire's next event (which may bring one), or its deadline.
static SyncOutcome wire_read(Run &run, Controller &c, const DeviceSync &sync, OpenDevice &d)
{
	if (d.gone || !drained(d) || run.ending)
		return answered();
	if (sync.nonblock || c.v() >= sync.deadline)
		return answered(sync.nonblock ? -EAGAIN : 0);
	return waits_until(std::min(next_record_due(c), sync.deadline));
}

// A sensor's read: done when a record is in its fd; a 'latest' sensor
// answers with the world now, and so does a stream once the run is ending
// (the world has stopped; its last state stands: its records still queued
// are of times that will not come). Else it waits for its next record.
static SyncOutcome sensor_read(Run &run, Controller &c, const DeviceSync &sync, OpenDevice &d)
{
	if (!drained(d) || d.gone)
		return answered();
	if ((d.dev->cfg.latest || run.ending) && run.world) {
		std::vector<double> values;
		for (size_t i : d.dev->signals)
			run.world->read_sensed(i, values);
		std::string rec = format_record(d.dev->cfg.format, values);
		(void)!send(d.sock.get(), rec.data(), rec.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
		return answered();
	}
	if (sync.nonblock || next_record_due(c) == TCS_NEVER)
		return answered(sync.nonblock ? -EAGAIN : 0);
	return waits_until(d.queue.empty() ? d.next_due : d.queue.front().first);
}

static SyncOutcome serve_sync(Run &run, Controller &c, const DeviceSync &sync)
{
	if (sync.kind == TCS_SYNC_DRAIN)
		return drain(run, c, sync);
	if (sync.kind != TCS_SYNC_READ)
		return answered();
	OpenDevice &d = *c.devices[(size_t)sync.handle];
	return d.wire ? wire_read(run, c, sync, d) : sensor_read(run, c, sync, d);
}

bool raise_timers_in_read(Controller &c, int64_t at)
{
	if (!c.sync || c.next_timer() > at)
		return false;
	advance(c, at);
	// Its handlers run now, inside the read: their clocks read this time.
	c.publish_slice(c.cpu_at_end >= 0 ? c.cpu_at_end : c.cpu_now());
	c.raise_due_timers();
	return true;
}

// The world is at or past the controller's step: do what it asked. False
// when it must wait (then it is Blocked until its record, its wire's next
// event, or its deadline).
bool complete_sync(Run &run, Controller &c)
{
	run.wires.advance(c.v(), run.sim_ns, run.world.get());
	deliver(c);
	const DeviceSync sync = *c.sync;
	c.sync.reset();
	const SyncOutcome out = serve_sync(run, c, sync);
	if (out.answered) {
		owe_answer(c, TCS_WAKE_DEADLINE, out.result);
		return true;
	}
	c.sync = sync;
	c.wait.asked = out.until;
	block(run, c, { .deadline = out.until });
	return false;
}

} // namespace tcs
