// A CanBus driven by bytes, and its promises checked (see can_bus_promises.h):
// every frame accepted is delivered once, whole and unchanged; per source in
// order; intervals never overlap and last the frame's time; none starts
// before it is ready or before it was submitted; the bus is never idle while
// a frame waits; the winner of each start had the lowest arbitration field
// among the frames that contended; the busy time is the frames' times; and a
// refusal means a full queue.
#include "can_bus_promises.h"

#include <algorithm>
#include <cstring>
#include <deque>
#include <map>
#include <optional>
#include <tuple>
#include <vector>

#include "can_bus.h"
#include "can_frame_time.h"
#include "fuzz_target.h"

namespace {

using tcs::CanBus;
using tcs::CanDelivery;
using tcs::CanFrame;
using tcs_fuzz::check;

const int64_t kBitrates[] = { 1000000, 500000, 125000, 33333 };

struct Sent {
	CanFrame frame;
	int64_t ready, submitted_at; // submitted_at: the time the bus had been run to
	uint64_t seq;
};

bool same(const CanFrame &a, const CanFrame &b)
{
	return a.id == b.id && a.extended == b.extended && a.rtr == b.rtr && a.fd == b.fd && a.brs == b.brs &&
	       a.esi == b.esi && a.len == b.len && memcmp(a.data, b.data, sizeof a.data) == 0;
}

class Record {
public:
	Record(int64_t bitrate, int64_t data_bitrate) : bitrate_(bitrate), data_bitrate_(data_bitrate) {}

	void sent(uint32_t source, const CanFrame &f, int64_t ready, int64_t now)
	{
		queues_[source].push_back({ f, ready, now, seq_++ });
	}

	// One advance's deliveries, until the time it ran to.
	void delivered(const std::vector<CanDelivery> &ds, int64_t until)
	{
		for (const CanDelivery &d : ds) {
			auto q = queues_.find(d.source);
			check(q != queues_.end() && !q->second.empty());
			const Sent s = q->second.front();
			q->second.pop_front();
			check(same(d.frame, s.frame));
			check(d.end_ns - d.start_ns == tcs::can_frame_ns(d.frame, bitrate_, data_bitrate_));
			check(d.end_ns <= until && d.end_ns > last_until_);
			// Work-conserving: it starts as soon as the bus is free, it is
			// ready and it was submitted.
			check(d.start_ns == std::max({ s.ready, s.submitted_at, last_end_ }));
			last_end_ = d.end_ns;
			busy_ += d.end_ns - d.start_ns;
			check_won(d, s);
		}
		last_until_ = std::max(last_until_, until);
	}

	int64_t busy() const { return busy_; }
	size_t waiting() const
	{
		size_t n = 0;
		for (const auto &[source, q] : queues_)
			n += q.size();
		return n;
	}

private:
	// No other head that contended at its start would have won.
	void check_won(const CanDelivery &d, const Sent &s) const
	{
		const auto mine = std::make_tuple(tcs::can_arbitration_key(s.frame), s.ready, s.seq);
		for (const auto &[source, q] : queues_) {
			if (q.empty() || source == d.source)
				continue;
			const Sent &h = q.front();
			if (h.ready > d.start_ns || h.submitted_at >= d.start_ns)
				continue;
			check(std::make_tuple(tcs::can_arbitration_key(h.frame), h.ready, h.seq) > mine);
		}
	}

	int64_t bitrate_, data_bitrate_;
	std::map<uint32_t, std::deque<Sent>> queues_;
	int64_t last_end_ = INT64_MIN, last_until_ = INT64_MIN;
	int64_t busy_ = 0;
	uint64_t seq_ = 0;
};

// Reads a byte; zeros past the end.
uint8_t take(const uint8_t *&data, size_t &size)
{
	if (size == 0)
		return 0;
	size--;
	return *data++;
}

CanFrame frame_from(const uint8_t *&data, size_t &size)
{
	CanFrame f;
	const uint8_t flags = take(data, size), len = take(data, size);
	f.extended = flags & 1;
	f.rtr = flags & 2;
	f.fd = flags & 4;
	f.brs = f.fd && (flags & 8);
	if (f.fd)
		f.rtr = false;
	uint32_t id = uint32_t(take(data, size)) << 8 | take(data, size);
	if (f.extended)
		id = id << 16 | uint32_t(take(data, size)) << 8 | take(data, size);
	f.id = id & (f.extended ? 0x1FFFFFFF : 0x7FF);
	f.len = f.fd ? tcs::can_fd_len(len % 65) : len % 9;
	const uint8_t fill = take(data, size);
	if (!f.rtr)
		for (int i = 0; i < f.len; i++)
			f.data[i] = uint8_t(fill + i * (fill >> 4));
	return f;
}

} // namespace

void can_bus_ops(const uint8_t *data, size_t size)
{
	const uint8_t config = take(data, size);
	const int64_t bitrate = kBitrates[config & 3];
	const int64_t data_bitrate = config & 4 ? 5000000 : 0;
	const size_t max_queued = config >> 3 & 15;
	CanBus bus(bitrate, data_bitrate, max_queued);
	Record record(bitrate, data_bitrate);
	int64_t now = INT64_MIN; // what the bus was last run to
	auto run_to = [&](int64_t until) {
		record.delivered(bus.advance(until), until);
		now = std::max(now, until);
	};
	while (size > 0) {
		const uint8_t op = take(data, size);
		switch (op & 3) {
		case 0:
		case 1: {
			const uint32_t source = op >> 2 & 7;
			const CanFrame f = frame_from(data, size);
			const int64_t base = now == INT64_MIN ? 0 : now;
			const int64_t ready = base + (int64_t(take(data, size)) - 64) * 1000;
			const size_t before = bus.queued(source);
			if (bus.submit(source, f, ready)) {
				check(before < max_queued && bus.queued(source) == before + 1);
				record.sent(source, f, ready, now);
			} else {
				check(before == max_queued && bus.queued(source) == before);
			}
			break;
		}
		case 2: {
			const int64_t step = (int64_t(take(data, size)) << 8 | take(data, size)) * 50;
			run_to((now == INT64_MIN ? 0 : now) + step - 1000);
			break;
		}
		default: {
			const std::optional<int64_t> end = bus.next_end();
			check(end.has_value() == (record.waiting() > 0));
			if (!end)
				break;
			check(*end > now);
			const size_t left = record.waiting();
			run_to(*end);
			check(record.waiting() < left); // the frame it named ended there
		}
		}
	}
	// Everything accepted goes out, once.
	run_to(INT64_MAX / 4);
	check(record.waiting() == 0 && !bus.next_end().has_value());
	check(bus.busy_ns() == record.busy());
}

std::string can_bus_seed()
{
	// 1 Mbit/s, 5 Mbit/s data, 10 a queue; submits from 3 sources,
	// advances, next_end.
	std::string s = "\x01";
	s += char(10 << 3 | 4 | 0);
	s += std::string("\x00\x00\x08\x07\x00\x55\x40", 7);             // source 0: 0x700
	s += std::string("\x04\x00\x08\x03\x00\xAA\x41", 7);             // source 1: 0x300
	s += std::string("\x08\x0D\x40\x00\x10\x00\x00\xFF\x42", 9);     // source 2: FD BRS, 64 bytes
	s += std::string("\x0C\x03\x04\x12\x34\x56\x78\x00\x40", 9);     // source 3: extended remote
	s += std::string("\x02\x01\x00", 3);                             // advance
	s += std::string("\x03", 1);                                     // to next_end
	s += std::string("\x00\x00\x08\x00\x01\x00\x00", 7);             // source 0: 0x001, in the past
	s += std::string("\x03\x03\x02\x00\x00", 5);                     // next_end, then more
	return s;
}
