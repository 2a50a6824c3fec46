// A CAN bus in virtual time: the nodes' transmit queues, arbitration, and
// each frame's time on the wire (can_frame_time.h).
//
// Each source (a socket, a motor) has a FIFO like a Linux netdev's transmit
// queue. Whenever the bus is idle, the frames at the heads of the queues
// that are ready contend and the one with the lowest arbitration field, as
// its bits are sent, wins: the identifier, then RTR (a data frame before a
// remote frame), then IDE (a standard frame before an extended one with the
// same 11-bit base). A frame that becomes ready while another is on the
// wire waits for the bus to be idle and contends then; a queued frame that
// has not started is overtaken by a higher-priority one that becomes ready
// before it starts. Frames of one source never reorder.
//
// Past what arbitration decides (the same field), this picks a classic
// frame before an FD one (where the real bus has a bit error), then the
// earlier ready, then the earlier submitted: the real bus would have two
// nodes send the same identifier, which a bus must not do.
//
// Times are virtual nanoseconds; a frame's end includes its intermission,
// so the next may start at it. Time saturates at INT64_MAX, never wraps.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <vector>

#include "can_frame.h"

namespace tcs {

struct CanDelivery {
	CanFrame frame;
	uint32_t source = 0;
	int64_t start_ns = 0, end_ns = 0;
};

// The frame's arbitration field as its bits are sent, a lower value
// winning; the last bit is FDF (classic first).
uint64_t can_arbitration_key(const CanFrame &frame);

class CanBus {
public:
	// bitrate, data_bitrate: bit/s (can_frame_ns); max_queued: frames a
	// source may have waiting (Linux's txqueuelen for CAN is 10).
	CanBus(int64_t bitrate, int64_t data_bitrate, size_t max_queued = 10);

	// Queues the frame from source, ready to go at ready_ns (it starts no
	// earlier, nor before the time the bus was last advanced to). False
	// when the source's queue is full (what sendmsg reports as ENOBUFS).
	bool submit(uint32_t source, const CanFrame &frame, int64_t ready_ns);
	// When the frame on the wire ends; when idle, when the frame that wins
	// next would end if nothing else is submitted before it starts; none
	// when nothing is queued.
	std::optional<int64_t> next_end() const;
	// When the frame that wins next starts, while the bus is idle; none
	// when a frame is on the wire (its end is the next start) or nothing
	// is queued. Advanced to it, the frame leaves its queue (queued()).
	std::optional<int64_t> next_start() const;
	// Runs the bus up to until_ns: every frame whose transmission ended
	// at or before it, in order. A frame that started at or before it is
	// on the wire: it can no longer be overtaken.
	std::vector<CanDelivery> advance(int64_t until_ns);
	// How long frames have occupied the bus up to the time it was last
	// advanced to (intermission included), for a bus-load figure.
	int64_t busy_ns() const;
	// Frames waiting in source's queue (not the one on the wire).
	size_t queued(uint32_t source) const;

private:
	struct Pending {
		CanFrame frame;
		int64_t ready_ns;
		uint64_t seq; // submission order, for ties
	};
	// The source whose head wins if the bus is idle from idle_from, and
	// when it starts; none when nothing is queued.
	std::optional<std::pair<uint32_t, int64_t>> winner() const;

	int64_t bitrate_, data_bitrate_;
	size_t max_queued_;
	std::map<uint32_t, std::deque<Pending>> queues_; // no empty queue kept
	std::optional<CanDelivery> wire_;                // the frame being sent
	int64_t idle_from_ = INT64_MIN;                  // when the bus is idle, since
	int64_t now_ = INT64_MIN;                        // the last advance's until
	int64_t busy_done_ = 0;                          // frames ended
	uint64_t seq_ = 0;
};

} // namespace tcs
