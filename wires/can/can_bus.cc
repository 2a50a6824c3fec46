// CanBus: queues, arbitration and wire time (see can_bus.h).
#include "can_bus.h"

#include <algorithm>
#include <tuple>

#include "can_frame_time.h"

namespace tcs {

namespace {

int64_t add_saturating(int64_t a, int64_t b)
{
	int64_t sum;
	return __builtin_add_overflow(a, b, &sum) ? (b > 0 ? INT64_MAX : INT64_MIN) : sum;
}

} // namespace

uint64_t can_arbitration_key(const CanFrame &f)
{
	const bool rtr = f.rtr && !f.fd; // FD sends RRS, dominant
	uint32_t field;
	if (f.extended)
		// base (11), SRR (recessive), IDE (recessive), extension (18), RTR
		field = ((f.id >> 18) & 0x7FF) << 21 | 1u << 20 | 1u << 19 | (f.id & 0x3FFFF) << 1 | rtr;
	else
		// id (11), RTR, IDE (dominant); what follows is no longer arbitration
		field = (f.id & 0x7FF) << 21 | uint32_t(rtr) << 20;
	return uint64_t(field) << 1 | f.fd;
}

CanBus::CanBus(int64_t bitrate, int64_t data_bitrate, size_t max_queued)
	: bitrate_(bitrate), data_bitrate_(data_bitrate), max_queued_(max_queued)
{
}

bool CanBus::submit(uint32_t source, const CanFrame &frame, int64_t ready_ns)
{
	std::deque<Pending> &q = queues_[source];
	if (q.size() >= max_queued_) {
		if (q.empty())
			queues_.erase(source);
		return false;
	}
	q.push_back({ frame, ready_ns, seq_++ });
	return true;
}

std::optional<std::pair<uint32_t, int64_t>> CanBus::winner() const
{
	if (queues_.empty())
		return std::nullopt;
	int64_t start = INT64_MAX;
	for (const auto &[source, q] : queues_)
		start = std::min(start, q.front().ready_ns);
	start = std::max(start, idle_from_);
	const Pending *best = nullptr;
	uint32_t best_source = 0;
	for (const auto &[source, q] : queues_) {
		const Pending &p = q.front();
		if (p.ready_ns > start)
			continue;
		if (!best || std::make_tuple(can_arbitration_key(p.frame), p.ready_ns, p.seq) <
				     std::make_tuple(can_arbitration_key(best->frame), best->ready_ns, best->seq)) {
			best = &p;
			best_source = source;
		}
	}
	return std::make_pair(best_source, start);
}

std::optional<int64_t> CanBus::next_end() const
{
	if (wire_)
		return wire_->end_ns;
	const auto w = winner();
	if (!w)
		return std::nullopt;
	const CanFrame &f = queues_.at(w->first).front().frame;
	return add_saturating(w->second, can_frame_ns(f, bitrate_, data_bitrate_));
}

std::optional<int64_t> CanBus::next_start() const
{
	if (wire_)
		return std::nullopt;
	const auto w = winner();
	if (!w)
		return std::nullopt;
	return w->second;
}

std::vector<CanDelivery> CanBus::advance(int64_t until_ns)
{
	std::vector<CanDelivery> out;
	if (until_ns < now_)
		return out;
	for (;;) {
		if (wire_) {
			if (wire_->end_ns > until_ns)
				break;
			busy_done_ = add_saturating(busy_done_, wire_->end_ns - wire_->start_ns);
			idle_from_ = wire_->end_ns;
			out.push_back(*wire_);
			wire_.reset();
			continue;
		}
		const auto w = winner();
		if (!w || w->second > until_ns)
			break;
		auto q = queues_.find(w->first);
		CanDelivery d;
		d.frame = q->second.front().frame;
		d.source = w->first;
		d.start_ns = w->second;
		d.end_ns = add_saturating(d.start_ns, can_frame_ns(d.frame, bitrate_, data_bitrate_));
		q->second.pop_front();
		if (q->second.empty())
			queues_.erase(q);
		wire_ = d;
	}
	now_ = until_ns;
	// Idle up to until: nothing submitted later may start in the past.
	if (!wire_)
		idle_from_ = std::max(idle_from_, until_ns);
	return out;
}

int64_t CanBus::busy_ns() const
{
	if (!wire_)
		return busy_done_;
	return add_saturating(busy_done_, std::min(now_, wire_->end_ns) - wire_->start_ns);
}

size_t CanBus::queued(uint32_t source) const
{
	const auto q = queues_.find(source);
	return q == queues_.end() ? 0 : q->second.size();
}

} // namespace tcs
