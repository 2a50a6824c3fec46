// A frame's bits on the wire and their time (see can_frame_time.h).
#include "can_frame_time.h"

#include <algorithm>

namespace tcs {

namespace {

// After the CRC sequence: CRC delimiter, ACK slot, ACK delimiter, EOF (7),
// intermission (3).
constexpr int kTailBits = 1 + 2 + 7 + 3;

// The bits of a frame up to where stuffing ends, as sent (0 dominant).
class Bits {
public:
	void put(uint32_t value, int width)
	{
		for (int i = width - 1; i >= 0; i--)
			bit_[n_++] = (value >> i) & 1;
	}
	int size() const { return n_; }
	// CRC-15 of the bits so far, initial value 0.
	uint32_t crc15() const
	{
		uint32_t crc = 0;
		for (int i = 0; i < n_; i++) {
			const bool top = ((crc >> 14) & 1) != bit_[i];
			crc = (crc << 1) & 0x7FFF;
			if (top)
				crc ^= 0x4599;
		}
		return crc;
	}
	// The stuff bits the bits need; *after_k counts those of them inserted
	// after bit k or a later one. final_counts: whether five equal bits
	// ending the stream add one.
	int stuff_bits(int k, int *after_k, bool final_counts) const
	{
		int count = 0, run = 0;
		bool last = false;
		*after_k = 0;
		for (int i = 0; i < n_; i++) {
			run = i > 0 && bit_[i] == last ? run + 1 : 1;
			last = bit_[i];
			if (run < 5 || (i == n_ - 1 && !final_counts))
				continue;
			count++;
			if (i >= k)
				(*after_k)++;
			// The stuff bit is the complement, and starts the next run.
			last = !last;
			run = 1;
		}
		return count;
	}

private:
	// The longest: an extended FD frame's 41 bits and 64 bytes of data.
	bool bit_[41 + 64 * 8] = {};
	int n_ = 0;
};

// SOF and the identifier as sent: the base id, then for an extended frame
// SRR, IDE and the extension. What follows (RTR/RRS, IDE of a standard
// frame) is the caller's.
void put_id(Bits &b, const CanFrame &f)
{
	b.put(0, 1);
	if (f.extended) {
		b.put((f.id >> 18) & 0x7FF, 11);
		b.put(1, 1); // SRR
		b.put(1, 1); // IDE
		b.put(f.id & 0x3FFFF, 18);
	} else {
		b.put(f.id & 0x7FF, 11);
	}
}

void put_data(Bits &b, const CanFrame &f, int len)
{
	for (int i = 0; i < len; i++)
		b.put(f.data[i], 8);
}

CanFrameBits classic_bits(const CanFrame &f)
{
	Bits b;
	put_id(b, f);
	b.put(f.rtr, 1);
	b.put(0, 2); // IDE and r0, or r1 and r0
	const int len = can_dlc(f);
	b.put(len, 4);
	if (!f.rtr)
		put_data(b, f, len);
	b.put(b.crc15(), 15);
	int unused;
	return { b.size() + b.stuff_bits(0, &unused, true) + kTailBits, 0 };
}

CanFrameBits fd_bits(const CanFrame &f)
{
	Bits b;
	put_id(b, f);
	b.put(0, 1); // RRS
	if (!f.extended)
		b.put(0, 1); // IDE
	b.put(1, 1); // FDF
	b.put(0, 1); // res
	const int brs_at = b.size();
	b.put(f.brs, 1);
	b.put(f.esi, 1);
	b.put(can_dlc(f), 4);
	const int len = can_fd_len(f.len);
	put_data(b, f, len);
	// Stuff count, CRC and fixed stuff bits.
	const int crc_field = len <= 16 ? 4 + 17 + 6 : 4 + 21 + 7;
	int stuff_after_brs;
	const int stuff = b.stuff_bits(brs_at, &stuff_after_brs, false);
	if (!f.brs)
		return { b.size() + stuff + crc_field + kTailBits, 0 };
	const int data = (b.size() - brs_at - 1) + stuff_after_brs + crc_field;
	return { brs_at + 1 + (stuff - stuff_after_brs) + kTailBits, data };
}

} // namespace

CanFrameBits can_frame_bit_split(const CanFrame &frame)
{
	return frame.fd ? fd_bits(frame) : classic_bits(frame);
}

int can_frame_bits(const CanFrame &frame)
{
	const CanFrameBits bits = can_frame_bit_split(frame);
	return bits.nominal + bits.data;
}

int64_t can_bit_ns(int64_t bitrate)
{
	const int64_t r = std::clamp<int64_t>(bitrate, 1, 1000000000);
	return std::max<int64_t>(1, (1000000000 + r / 2) / r);
}

int64_t can_frame_ns(const CanFrame &frame, int64_t bitrate, int64_t data_bitrate)
{
	const CanFrameBits bits = can_frame_bit_split(frame);
	return bits.nominal * can_bit_ns(bitrate) + bits.data * can_bit_ns(data_bitrate > 0 ? data_bitrate : bitrate);
}

} // namespace tcs
