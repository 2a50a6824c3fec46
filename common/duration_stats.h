// Least, median and most of a stream of durations in constant memory, for
// figures gathered once per simulation step over runs of any length: the
// median is read from a histogram with bins 2^(1/16) wide (within 2.2 %).
#pragma once

#include <array>
#include <cstdint>

namespace tcs {

class DurationStats {
public:
	void add(int64_t ns);
	uint64_t count() const { return count_; }
	int64_t min() const { return count_ ? min_ : 0; }
	int64_t max() const { return count_ ? max_ : 0; }
	int64_t median() const;

private:
	static constexpr int kPerOctave = 16;
	static constexpr int kBins = 64 * kPerOctave; // up to 2^64 ns
	std::array<uint64_t, kBins> bins_{};
	uint64_t count_ = 0;
	int64_t min_ = INT64_MAX, max_ = 0;
};

} // namespace tcs
