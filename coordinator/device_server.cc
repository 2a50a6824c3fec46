// The world's devices as the coordinator serves them: see device_server.h.
// Causality and zero-order hold (docs/DESIGN.md §2, §4): a sensor record due at
// T carries the world at the last step boundary <= T; it is made when the
// world reaches that boundary and put into the controller's fd when the
// controller's virtual time reaches T. A command written at V is held from
// the first boundary >= V.
#include "device_server.h"

#include <sys/ioctl.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstring>

#include <linux/sockios.h>

#include "tcs/protocol.h"
#include "wire_bus.h"

namespace tcs {

namespace {
// Records made but never read: a real sensor's buffer overflows too.
constexpr size_t kMaxQueued = 4096;
} // namespace

Status DeviceServer::bind(const std::vector<DeviceConfig> &devices, const SimWorld *world, Warn warn)
{
	warn_ = std::move(warn);
	for (const auto &cfg : devices) {
		BoundDevice d;
		d.cfg = cfg;
		if (is_wire(cfg.kind)) {
			devices_.push_back(std::move(d));
			continue;
		}
		if (!world)
			return Error{ cfg.path + ": a device needs a world with signals" };
		for (const auto &name : cfg.signals) {
			long i = world->find(name);
			if (i < 0)
				return Error{ cfg.path + ": unknown signal '" + name + "'" };
			const tcs_sim_signal_info &info = world->signal((size_t)i);
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

void DeviceServer::make_records(OpenDevice &d, int64_t until, const SimWorld *world)
{
	const BoundDevice &dev = *d.dev;
	if (!world || dev.cfg.kind != TCS_DEVICE_SENSOR || dev.cfg.latest || dev.cfg.period_ns <= 0)
		return;
	std::vector<double> values;
	for (size_t i : dev.signals)
		world->read_sensed(i, values);
	std::string record = format_record(dev.cfg.format, values);
	for (; d.next_due < until; d.next_due += dev.cfg.period_ns) {
		if (d.queue.size() == kMaxQueued) {
			d.queue.pop_front();
			if (d.dropped++ == 0)
				warn_(dev.cfg.path + ": more than " + std::to_string(kMaxQueued) +
					  " records unread: the oldest are dropped");
		}
		d.queue.emplace_back(d.next_due, record);
	}
}

void DeviceServer::fill_streams(const std::vector<std::unique_ptr<Controller>> &ctls, int64_t until, const SimWorld *world)
{
	for (auto &c : ctls)
		for (auto &d : c->devices)
			if (!d->gone)
				make_records(*d, until, world);
}

// A record goes into an fd only once the controller has read all that the
// fd held: so a reader that stalls keeps at most what it had then, and the
// records waiting here, kMaxQueued at most, lose their oldest first. (Filled
// whenever there was room, the fd's buffer would keep hundreds of the oldest
// records and the drops would cut out the middle.)
bool drained(const OpenDevice &d)
{
	int unread = 0;
	return ioctl(d.sock.get(), SIOCOUTQ, &unread) == 0 && unread == 0;
}

// A CAN frame going into its socket carries the socket's drops so far, as
// the kernel's sock_queue_rcv_skb stamps each frame it queues (what
// SO_RXQ_OVFL reports with it).
static void stamp_drops(const WirePort &p, std::string &packet)
{
	if (p.kind != TCS_DEVICE_CAN || packet.size() < sizeof(tcs_wire_can_rx))
		return;
	const uint32_t drops = uint32_t(p.dropped);
	memcpy(packet.data() + offsetof(tcs_wire_can_rx, drops), &drops, sizeof drops);
}

// A wire's arrivals go into its fd as they come due, whether the
// controller has read what is there or not: a tty or a socket buffers them.
static void deliver_wire(OpenDevice &d, int64_t now)
{
	WirePort &p = *d.wire;
	while (!d.gone && !p.arrivals.empty() && p.arrivals.front().first <= now) {
		std::string &bytes = p.arrivals.front().second;
		stamp_drops(p, bytes);
		ssize_t n = send(d.sock.get(), bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
		if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS)) {
			// Its buffer is full: a reader that does not read loses the
			// oldest, as a tty's or a socket's overflow does.
			p.arrivals.pop_front();
			p.dropped++;
			continue;
		}
		if (n < 0) {
			d.gone = p.gone = true;
			p.arrivals.clear();
			break;
		}
		if ((size_t)n < bytes.size()) {
			bytes.erase(0, (size_t)n);
			continue;
		}
		p.arrivals.pop_front();
	}
}

void deliver(Controller &c)
{
	for (auto &d : c.devices) {
		if (d->wire) {
			deliver_wire(*d, c.v());
			continue;
		}
		if (d->gone || d->queue.empty() || d->queue.front().first > c.v() || !drained(*d))
			continue;
		while (!d->gone && !d->queue.empty() && d->queue.front().first <= c.v()) {
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

int64_t next_record_due(const Controller &c)
{
	int64_t due = TCS_NEVER;
	for (const auto &d : c.devices) {
		if (d->wire && !d->gone) {
			if (!d->wire->arrivals.empty())
				due = std::min(due, d->wire->arrivals.front().first);
			if (d->wire->bus)
				due = std::min(due, d->wire->bus->next_event());
			continue;
		}
		if (d->gone || d->dev->cfg.kind != TCS_DEVICE_SENSOR || d->dev->cfg.latest)
			continue;
		if (d->queue.empty()) {
			due = std::min(due, d->next_due);
			continue;
		}
		// One due by its time and still queued waits for the program to
		// read the record in its fd (deliver): no wait ends for it, or a
		// poll of other fds from a handler that interrupted that read
		// would be woken for it again and again at the same time.
		int64_t at = d->queue.front().first;
		if (at > c.v() || drained(*d))
			due = std::min(due, at);
	}
	return due;
}

bool DeviceServer::take_commands(Controller &c, OpenDevice &d, bool written_lazily, Trace &trace)
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
		if (trace.is_open())
			trace.command(c.id, dev.cfg.path, c.v(), values, false);
		if (on_command)
			on_command(c, dev.cfg.path, &values);
		commands_.emplace_back(c.v(), &dev, std::move(values));
	}
	if (!ok) {
		if (trace.is_open())
			trace.command(c.id, dev.cfg.path, c.v(), {}, true);
		if (on_command)
			on_command(c, dev.cfg.path, nullptr);
		dev.malformed++;
		// The preload vouched for a lazy write's records: only a write
		// around its hooks (a raw system call) can get here.
		warn_(c.name + ": " + dev.cfg.path + ": malformed record (" + why + "): " +
			  (written_lazily ? "written around tcs's hooks, it is dropped"
					  : "the write fails with EINVAL") +
			  " and the last valid command stays in force");
	}
	return ok;
}

void DeviceServer::take_lazy_commands(Controller &c, int64_t except, Trace &trace)
{
	for (uint64_t bits = c.take_lazy_handles(); bits != 0; bits &= bits - 1) {
		size_t h = (size_t)__builtin_ctzll(bits);
		if ((int64_t)h != except && h < c.devices.size() && c.devices[h]->dev->cfg.kind == TCS_DEVICE_ACTUATOR)
			take_commands(c, *c.devices[h], true, trace);
	}
}

} // namespace tcs
