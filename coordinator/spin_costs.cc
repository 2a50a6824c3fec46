// Measuring a spin's calls (spin_costs.h): batches timed by the monotonic
// clock, the least per call taken; a millisecond or two at start-up.
#include "spin_costs.h"

#include <fcntl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>

#include "clock_ns.h"
#include "unique_fd.h"

namespace tcs {

namespace {
constexpr int kBatches = 9;
constexpr int kClockReads = 2000;
constexpr int kEmptyReads = 200;

template <typename Call> int64_t least_per_call(int n, Call call)
{
	int64_t best = INT64_MAX;
	for (int b = 0; b < kBatches; b++) {
		int64_t start = clock_ns(CLOCK_MONOTONIC);
		for (int i = 0; i < n; i++)
			call();
		best = std::min(best, (clock_ns(CLOCK_MONOTONIC) - start) / n);
	}
	return std::max<int64_t>(best, 1);
}
} // namespace

SpinCosts measure_spin_costs()
{
	SpinCosts costs = kNominalSpinCosts;
	costs.clock_ns = least_per_call(kClockReads, [] {
		struct timespec ts;
		clock_gettime(CLOCK_MONOTONIC, &ts);
		__asm__ __volatile__("" : : "r"(&ts) : "memory");
	});
	int fds[2];
	if (pipe2(fds, O_NONBLOCK | O_CLOEXEC) == 0) {
		UniqueFd rd(fds[0]), wr(fds[1]);
		costs.read_ns = least_per_call(kEmptyReads, [&rd] {
			char byte;
			ssize_t r = read(rd.get(), &byte, 1);
			(void)r;
		});
	}
	return costs;
}

} // namespace tcs
