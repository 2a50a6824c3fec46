// DurationStats: a log-spaced histogram beside the exact extremes.
#include "duration_stats.h"

#include <algorithm>
#include <cmath>

namespace tcs {

namespace {

int bin_of(int64_t ns, int per_octave, int bins)
{
	if (ns <= 1)
		return 0;
	int b = (int)std::floor(std::log2((double)ns) * per_octave);
	return std::clamp(b, 0, bins - 1);
}

} // namespace

void DurationStats::add(int64_t ns)
{
	ns = std::max<int64_t>(ns, 0);
	bins_[(size_t)bin_of(ns, kPerOctave, kBins)]++;
	count_++;
	min_ = std::min(min_, ns);
	max_ = std::max(max_, ns);
}

int64_t DurationStats::median() const
{
	if (!count_)
		return 0;
	uint64_t seen = 0;
	for (int b = 0; b < kBins; b++) {
		seen += bins_[(size_t)b];
		if (2 * seen > count_) {
			// The bin's geometric middle, kept within the exact extremes.
			double mid = std::exp2(((double)b + 0.5) / kPerOctave);
			return std::clamp((int64_t)std::llround(mid), min_, max_);
		}
	}
	return max_;
}

} // namespace tcs
