// One direction of a UART in virtual time: when each byte written to the
// line has arrived at the other end, for the coordinator to hand over to
// the reader what has arrived by a given time. Bytes are counted, not
// kept: their content stays with the caller.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

#include "error.h"

namespace tcs {

// The bits a UART sends for a byte: a start bit, 5 to 8 data bits, a
// parity bit if any, and 1 or 2 stop bits (8N1: 10).
Result<int> serial_frame_bits(int data_bits, bool parity, int stop_bits);

// The same from a termios c_cflag (CSIZE, PARENB, CSTOPB), as
// tcsetattr() or TCSETS2 was given it.
int serial_frame_bits_cflag(uint32_t c_cflag);

class SerialDirection {
public:
	// A baud or a frame below 1 is taken as 1 (the caller refuses them).
	SerialDirection(int64_t baud, int bits_per_byte);

	// Queues n bytes handed to the line at ready_ns behind those still on
	// the wire; returns when the last of them has arrived (n = 0: ready_ns,
	// or when the wire is idle if that is later).
	int64_t send(size_t n, int64_t ready_ns);

	// How many bytes have arrived by t_ns since the last take(): they are
	// the reader's now, in the order sent.
	size_t take(int64_t t_ns);

	// Sent and not yet taken; the i-th of them (from 0, i < pending())
	// arrives at arrival(i).
	size_t pending() const { return pending_; }
	int64_t arrival(size_t i) const;

	// When the last byte sent has arrived (what tcdrain() waits for).
	int64_t idle_at() const { return idle_; }

	// tcflush(): the bytes not arrived by t_ns are dropped, the last ones
	// sent; returns how many. The wire is free from t_ns.
	size_t discard(int64_t t_ns);

	// For the bytes sent from now on; those on the wire keep their rate.
	void set_baud(int64_t baud, int bits_per_byte);
	int64_t baud() const { return baud_; }
	int bits_per_byte() const { return bits_; }

private:
	// Bytes sent back to back: byte k (from 0) of a run arrives at start +
	// floor((k + 1) * bits * 1e9 / baud), so that rounding never drifts.
	struct Run {
		int64_t start;
		int64_t baud;
		int bits;
		uint64_t sent;
		uint64_t taken;
	};
	static int64_t end_of(const Run &r, uint64_t k);
	static uint64_t arrived_by(const Run &r, int64_t t_ns);

	std::deque<Run> runs_;
	int64_t baud_;
	int bits_;
	int64_t idle_ = INT64_MIN;
	size_t pending_ = 0;
};

} // namespace tcs
