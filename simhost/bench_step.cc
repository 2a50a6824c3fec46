// Benchmark: the wall-clock cost of one step of the built-in models, as
// min / median / max over many steps, through the plug-in ABI. For 1000
// boxes this is the variable cost of the TCS paper's Figure 1. Prints
// figures; judges nothing.
//
//   simhost_step_bench [STEPS]     (default 1000)
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "tcs/simhost.h"

namespace {

double now_ns()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

int bench(const char *label, const struct tcs_sim_model &model, int steps)
{
	const struct tcs_simhost_plugin *p = tcs_simhost_ode_plugin();
	char err[256];
	double t0 = now_ns();
	tcs_sim *sim = p->create(&model, 1, 1000000, err, sizeof err);
	if (!sim) {
		fprintf(stderr, "%s: %s\n", label, err);
		return 1;
	}
	double created = now_ns() - t0;
	std::vector<double> ns;
	ns.reserve((size_t)steps);
	for (int i = 0; i < steps; i++) {
		t0 = now_ns();
		if (p->step(sim, err, sizeof err) != 0) {
			fprintf(stderr, "%s: %s\n", label, err);
			p->destroy(sim);
			return 1;
		}
		ns.push_back(now_ns() - t0);
	}
	p->destroy(sim);
	std::sort(ns.begin(), ns.end());
	printf("%-22s create %9.0f ns; per 1 ms step over %d: min %9.0f  median %9.0f  max %9.0f ns (max/min %.2f)\n",
	       label, created, steps, ns.front(), ns[ns.size() / 2], ns.back(), ns.back() / ns.front());
	return 0;
}

} // namespace

int main(int argc, char **argv)
{
	int steps = argc > 1 ? atoi(argv[1]) : 1000;
	if (steps < 1) {
		fprintf(stderr, "usage: %s [STEPS]\n", argv[0]);
		return 2;
	}
	const char *swing_k[] = { "initial_angle" };
	const double swing_v[] = { 1.0 };
	int r = 0;
	r |= bench("pendulum", { "p", "pendulum", swing_k, swing_v, 1 }, steps);
	r |= bench("cartpole", { "c", "cartpole", swing_k, swing_v, 1 }, steps);
	r |= bench("double_pendulum", { "d", "double_pendulum", nullptr, nullptr, 0 }, steps);
	r |= bench("boxes (1000)", { "b", "boxes", nullptr, nullptr, 0 }, steps);
	return r;
}
