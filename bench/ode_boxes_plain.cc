// ode_boxes_plain [--checksum] [STEPS]: the 1000-box world of simhost's
// `boxes` model stepped by a plain ODE program (no tcs code), STEPS 1 ms
// steps from creation (2000). Prints the median cost of a step and, with
// --checksum, a sum of every box's pose and twist at the end, to compare
// with `simhost_step_bench --checksum` (same steps: same sum).
#include <time.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "ode_boxes_plain.h"

namespace {

double now_ns()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

} // namespace

int main(int argc, char **argv)
{
	bool checksum = false;
	long steps = 2000;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--checksum") == 0) {
			checksum = true;
		} else if ((steps = atol(argv[i])) < 1) {
			fprintf(stderr, "usage: %s [--checksum] [STEPS]\n", argv[0]);
			return 2;
		}
	}

	dInitODE2(0);
	dAllocateODEDataForThread(dAllocateMaskAll);
	plain::Boxes w;
	plain::boxes_create(w);
	std::vector<double> ns;
	ns.reserve((size_t)steps);
	for (long i = 0; i < steps; i++) {
		double t0 = now_ns();
		if (!plain::boxes_step(w)) {
			fprintf(stderr, "%s: ODE could not allocate a step's memory\n", argv[0]);
			return 1;
		}
		ns.push_back(now_ns() - t0);
	}
	if (checksum)
		printf("checksum=%016" PRIx64 "\n", plain::boxes_checksum(w));
	plain::boxes_destroy(w);
	dCloseODE();

	std::sort(ns.begin(), ns.end());
	printf("steps=%ld\nplain_step_ns_median=%.0f\nplain_step_us_median=%.1f\n", steps, ns[ns.size() / 2],
	       ns[ns.size() / 2] / 1e3);
	return 0;
}
