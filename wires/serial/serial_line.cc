// SerialDirection: the runs of bytes on the wire and when each arrives
// (see serial_line.h).
#include "serial_line.h"

#include <asm/termbits.h>

#include <algorithm>

namespace tcs {

namespace {

constexpr int64_t kNsPerS = 1000000000;

int64_t saturated(__int128 v)
{
	return v > INT64_MAX ? INT64_MAX : v < INT64_MIN ? INT64_MIN : (int64_t)v;
}

} // namespace

Result<int> serial_frame_bits(int data_bits, bool parity, int stop_bits)
{
	if (data_bits < 5 || data_bits > 8)
		return Error{ "serial: " + std::to_string(data_bits) + " data bits (a UART sends 5 to 8)" };
	if (stop_bits != 1 && stop_bits != 2)
		return Error{ "serial: " + std::to_string(stop_bits) + " stop bits (1 or 2)" };
	return 1 + data_bits + (parity ? 1 : 0) + stop_bits;
}

int serial_frame_bits_cflag(uint32_t c_cflag)
{
	int data = 8;
	switch (c_cflag & CSIZE) {
	case CS5:
		data = 5;
		break;
	case CS6:
		data = 6;
		break;
	case CS7:
		data = 7;
		break;
	default:
		break;
	}
	return 1 + data + ((c_cflag & PARENB) ? 1 : 0) + ((c_cflag & CSTOPB) ? 2 : 1);
}

SerialDirection::SerialDirection(int64_t baud, int bits_per_byte)
    : baud_(std::max<int64_t>(baud, 1)), bits_(std::max(bits_per_byte, 1))
{
}

int64_t SerialDirection::end_of(const Run &r, uint64_t k)
{
	const __int128 bits = (__int128)(k + 1) * r.bits * kNsPerS;
	return saturated(r.start + bits / r.baud);
}

uint64_t SerialDirection::arrived_by(const Run &r, int64_t t_ns)
{
	if (t_ns < r.start)
		return 0;
	// The k with floor((k + 1) * bits * 1e9 / baud) <= t - start.
	const __int128 n = (((__int128)t_ns - r.start + 1) * r.baud - 1) / ((__int128)r.bits * kNsPerS);
	return n >= (__int128)r.sent ? r.sent : (uint64_t)n;
}

int64_t SerialDirection::send(size_t n, int64_t ready_ns)
{
	if (n == 0)
		return std::max(idle_, ready_ns);
	pending_ += n;
	if (!runs_.empty()) {
		Run &last = runs_.back();
		// Behind the last byte, at the same rate: the same run, so that
		// its bytes' times are exact however the writes were cut.
		if (ready_ns <= idle_ && last.baud == baud_ && last.bits == bits_ && last.sent > 0 &&
		    end_of(last, last.sent - 1) == idle_) {
			last.sent += n;
			idle_ = end_of(last, last.sent - 1);
			return idle_;
		}
		if (last.taken == last.sent)
			runs_.pop_back();
	}
	runs_.push_back(Run{ std::max(ready_ns, idle_), baud_, bits_, n, 0 });
	idle_ = end_of(runs_.back(), n - 1);
	return idle_;
}

size_t SerialDirection::take(int64_t t_ns)
{
	size_t got = 0;
	while (!runs_.empty()) {
		Run &r = runs_.front();
		const uint64_t now = std::max(arrived_by(r, t_ns), r.taken);
		got += now - r.taken;
		r.taken = now;
		// A later run starts after this one ends: none of it has arrived.
		if (r.taken < r.sent || runs_.size() == 1)
			break;
		runs_.pop_front();
	}
	pending_ -= got;
	return got;
}

int64_t SerialDirection::arrival(size_t i) const
{
	for (const Run &r : runs_) {
		const uint64_t left = r.sent - r.taken;
		if (i < left)
			return end_of(r, r.taken + i);
		i -= left;
	}
	return INT64_MAX;
}

size_t SerialDirection::discard(int64_t t_ns)
{
	size_t dropped = 0;
	for (Run &r : runs_) {
		const uint64_t kept = std::max(arrived_by(r, t_ns), r.taken);
		dropped += r.sent - kept;
		r.sent = kept;
	}
	if (dropped == 0)
		return 0;
	pending_ -= dropped;
	idle_ = t_ns; // a byte cut off on the wire is lost with the rest
	runs_.erase(std::remove_if(runs_.begin(), runs_.end(), [](const Run &r) { return r.taken == r.sent; }),
		    runs_.end());
	return dropped;
}

void SerialDirection::set_baud(int64_t baud, int bits_per_byte)
{
	baud_ = std::max<int64_t>(baud, 1);
	bits_ = std::max(bits_per_byte, 1);
}

} // namespace tcs
