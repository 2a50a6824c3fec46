// Benchmark: the wall-clock cost of one step of the built-in models, as
// min / median / max over many steps, through the plug-in ABI. For 1000
// boxes this is the variable cost of the TCS paper's Figure 1. Prints
// figures; judges nothing.
//
//   simhost_step_bench [--checksum] [STEPS]     (default 1000)
//
// --checksum also prints, per model, an FNV-1a sum of the bytes of every
// pose and twist signal after the last step: bench/ode_boxes_plain prints
// the same sum of its own world, to show both step the same state.
#include <time.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <vector>

#include "tcs/simhost.h"

namespace {

double now_ns()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

uint64_t state_checksum(const struct tcs_simhost_plugin *p, const tcs_sim *sim)
{
	uint64_t h = 0xcbf29ce484222325ull;
	for (size_t i = 0; i < p->signal_count(sim); i++) {
		const struct tcs_sim_signal_info *info = p->signal_info(sim, i);
		std::string_view name = info->name;
		if (!name.ends_with(".pose") && !name.ends_with(".twist"))
			continue;
		double v[7];
		p->read(sim, i, v);
		unsigned char bytes[sizeof v];
		memcpy(bytes, v, sizeof bytes);
		for (size_t b = 0; b < info->width * sizeof(double); b++)
			h = (h ^ bytes[b]) * 0x100000001b3ull;
	}
	return h;
}

int bench(const char *label, const struct tcs_sim_model &model, int steps, bool checksum)
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
	if (checksum)
		printf("%-22s checksum=%016" PRIx64 "\n", label, state_checksum(p, sim));
	p->destroy(sim);
	std::sort(ns.begin(), ns.end());
	printf("%-22s create %9.0f ns; per 1 ms step over %d: min %9.0f  median %9.0f  max %9.0f ns (max/min %.2f)\n",
	       label, created, steps, ns.front(), ns[ns.size() / 2], ns.back(), ns.back() / ns.front());
	return 0;
}

} // namespace

int main(int argc, char **argv)
{
	bool checksum = false;
	int steps = 1000;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--checksum") == 0) {
			checksum = true;
		} else if ((steps = atoi(argv[i])) < 1) {
			fprintf(stderr, "usage: %s [--checksum] [STEPS]\n", argv[0]);
			return 2;
		}
	}
	const char *swing_k[] = { "initial_angle" };
	const double swing_v[] = { 1.0 };
	int r = 0;
	r |= bench("pendulum", { "p", "pendulum", swing_k, swing_v, 1 }, steps, checksum);
	r |= bench("cartpole", { "c", "cartpole", swing_k, swing_v, 1 }, steps, checksum);
	r |= bench("double_pendulum", { "d", "double_pendulum", nullptr, nullptr, 0 }, steps, checksum);
	r |= bench("boxes (1000)", { "b", "boxes", nullptr, nullptr, 0 }, steps, checksum);
	return r;
}
