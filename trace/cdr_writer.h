// CdrWriter: a message in CDR (OMG XCDR1, little-endian, as ROS 2 writes
// it), the encoding of the trace's per-cycle topics: a 4-byte
// encapsulation header, then each field aligned to its own size, counted
// from the end of the header; strings and sequences prefixed by a uint32
// count (a string's includes its NUL). Header-only: the coordinator writes a
// few messages every cycle, each a handful of plain stores into one reused
// buffer (appending to a std::string field by field cost it more than the
// message's own numbers: docs/PERFORMANCE.md).
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

namespace tcs {

static_assert(std::endian::native == std::endian::little, "CdrWriter writes native stores as CDR_LE");

class CdrWriter {
public:
	// Starts a message in out, whose size is only ever grown (so that
	// a buffer reused for message after message stops allocating): the
	// message is its first size() bytes, view(); finish() cuts out to
	// them.
	explicit CdrWriter(std::string &out) : out_(out)
	{
		room(4);
		std::memcpy(p_, "\x00\x01\x00\x00", 4); // CDR_LE, no options
		at_ = 4;
	}

	template <typename T>
	void put(T v)
	{
		static_assert(std::is_arithmetic_v<T>);
		align(sizeof(T));
		room(sizeof(T));
		std::memcpy(p_ + at_, &v, sizeof(T));
		at_ += sizeof(T);
	}
	void put_bool(bool v) { put<uint8_t>(v ? 1 : 0); }
	void put_string(std::string_view s)
	{
		put<uint32_t>((uint32_t)s.size() + 1);
		put_bytes(s.data(), s.size());
		put<uint8_t>(0);
	}
	// A sequence's count; its elements follow with put*().
	void put_count(size_t n) { put<uint32_t>((uint32_t)n); }
	// n elements of a sequence of T, stored as this machine lays out T[]
	// (little-endian, and T's alignment holds within the sequence); none
	// is no padding either.
	template <typename T>
	void put_array(const T *v, size_t n)
	{
		static_assert(std::is_arithmetic_v<T>);
		if (n == 0)
			return;
		align(sizeof(T));
		put_bytes(v, n * sizeof(T));
	}
	// Bytes that follow where the last field ended, as they are: what the
	// caller laid out by CDR's rules itself.
	void put_bytes(const void *data, size_t n)
	{
		room(n);
		if (n)
			std::memcpy(p_ + at_, data, n);
		at_ += n;
	}
	// Room for n more bytes, aligned to `to` (relative to the header's
	// end), padded with zeros: where to store them, in place. Valid until
	// the next call; the caller fills all n.
	char *place(size_t n, size_t to = 1)
	{
		align(to);
		room(n);
		char *at = p_ + at_;
		at_ += n;
		return at;
	}

	size_t size() const { return at_; }
	std::string_view view() const { return { p_, at_ }; }
	void finish() { out_.resize(at_); }

private:
	// Inline, every field: a comparison; the buffer grows out of line.
	__attribute__((always_inline)) void room(size_t n)
	{
		if (__builtin_expect(at_ + n > out_.size(), 0))
			grow(n);
	}
	__attribute__((noinline)) void grow(size_t n)
	{
		out_.resize(std::max(at_ + n, 2 * out_.size() + 64));
		p_ = out_.data();
	}
	void align(size_t n)
	{
		size_t pad = (n - (at_ - 4) % n) % n;
		if (pad) {
			room(pad);
			std::memset(p_ + at_, 0, pad);
			at_ += pad;
		}
	}
	std::string &out_;
	char *p_ = out_.data();
	size_t at_ = 0;
};

} // namespace tcs
