// CdrWriter: a message in CDR (OMG XCDR1, little-endian, as ROS 2 writes
// it), the encoding of the trace's per-cycle topics: a 4-byte
// encapsulation header, then each field aligned to its own size, counted
// from the end of the header; strings and sequences prefixed by a uint32
// count (a string's includes its NUL). Header-only: the coordinator writes a
// few messages every cycle, each a handful of stores into one reused buffer.
#pragma once

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
	// Starts a message in out (cleared; its capacity is kept).
	explicit CdrWriter(std::string &out) : out_(out)
	{
		out_.assign("\x00\x01\x00\x00", 4); // CDR_LE, no options
	}

	template <typename T>
	void put(T v)
	{
		static_assert(std::is_arithmetic_v<T>);
		align(sizeof(T));
		char raw[sizeof(T)];
		std::memcpy(raw, &v, sizeof(T));
		out_.append(raw, sizeof(T));
	}
	void put_bool(bool v) { out_ += v ? '\1' : '\0'; }
	void put_string(std::string_view s)
	{
		put<uint32_t>((uint32_t)s.size() + 1);
		out_.append(s.data(), s.size());
		out_ += '\0';
	}
	// A sequence's count; its elements follow with put*().
	void put_count(size_t n) { put<uint32_t>((uint32_t)n); }

private:
	void align(size_t n)
	{
		size_t at = out_.size() - 4;
		if (size_t pad = (n - at % n) % n)
			out_.append(pad, '\0');
	}
	std::string &out_;
};

} // namespace tcs
