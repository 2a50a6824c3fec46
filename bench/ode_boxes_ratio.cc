// ode_boxes_ratio [--steps N] [--block B] [--rounds R]: the cost of a
// simhost step of the 1000-box world against the same world stepped by a
// plain ODE program (ode_boxes_plain.h), measured in one run.
//
// A world of boxes settles, so a step's cost depends on its index: each
// round creates both worlds fresh and steps each through the same indices
// 0..N-1, alternating blocks of B steps between them (the side that goes
// first alternates by round), so both do the same work under the same
// machine conditions. The figures are medians over blocks of the cost per
// step; at the end of each round the two states must be equal bit for bit.
// Prints key=value lines; judges nothing.
#include <time.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "ode_boxes_plain.h"
#include "tcs/simhost.h"

namespace {

double now_ns()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

double median(std::vector<double> v)
{
	std::sort(v.begin(), v.end());
	size_t n = v.size();
	return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

// The plug-in's boxes signals are box<i>.pose at 2i and .twist at 2i+1:
// the same sum as plain::boxes_checksum when the states are equal.
uint64_t simhost_checksum(const struct tcs_simhost_plugin *p, const tcs_sim *sim)
{
	uint64_t h = plain::kFnvBasis;
	for (size_t i = 0; i < 2 * plain::kCount; i++) {
		double v[7];
		p->read(sim, i, v);
		h = plain::fnv1a(h, v, i % 2 ? 6 : 7);
	}
	return h;
}

struct Options {
	long steps = 2000;
	long block = 200;
	long rounds = 3;
};

bool parse(int argc, char **argv, Options &o)
{
	for (int i = 1; i + 1 < argc; i += 2) {
		long v = atol(argv[i + 1]);
		if (v < 1)
			return false;
		if (strcmp(argv[i], "--steps") == 0)
			o.steps = v;
		else if (strcmp(argv[i], "--block") == 0)
			o.block = v;
		else if (strcmp(argv[i], "--rounds") == 0)
			o.rounds = v;
		else
			return false;
	}
	return argc % 2 == 1 && o.steps % o.block == 0;
}

} // namespace

int main(int argc, char **argv)
{
	Options o;
	if (!parse(argc, argv, o)) {
		fprintf(stderr, "usage: %s [--steps N] [--block B] [--rounds R]  (B divides N)\n", argv[0]);
		return 2;
	}
	dInitODE2(0);
	dAllocateODEDataForThread(dAllocateMaskAll);
	const struct tcs_simhost_plugin *p = tcs_simhost_ode_plugin();
	const struct tcs_sim_model model = { "b", "boxes", nullptr, nullptr, 0 };
	char err[256];

	std::vector<double> plain_ns, simhost_ns, pair_ratio; // per step, one per block
	double plain_total = 0, simhost_total = 0;
	uint64_t plain_sum = 0, simhost_sum = 0;
	bool same = true;
	for (long r = 0; r < o.rounds; r++) {
		plain::Boxes w;
		plain::boxes_create(w);
		tcs_sim *sim = p->create(&model, 1, 1000000, err, sizeof err);
		if (!sim || p->signal_count(sim) != 2 * plain::kCount + 1) {
			fprintf(stderr, "%s: simhost world: %s\n", argv[0], sim ? "unexpected signals" : err);
			return 1;
		}
		for (long b = 0; b < o.steps / o.block; b++) {
			double ns[2]; // plain, simhost
			for (int k = 0; k < 2; k++) {
				bool simhost = (k + r) % 2 == 1;
				double t0 = now_ns();
				for (long i = 0; i < o.block; i++) {
					bool ok = simhost ? p->step(sim, err, sizeof err) == 0 : plain::boxes_step(w);
					if (!ok) {
						fprintf(stderr, "%s: %s step failed: %s\n", argv[0],
							simhost ? "simhost" : "plain", simhost ? err : "out of memory");
						return 1;
					}
				}
				ns[simhost] = (now_ns() - t0) / (double)o.block;
			}
			plain_ns.push_back(ns[0]);
			simhost_ns.push_back(ns[1]);
			pair_ratio.push_back(ns[1] / ns[0]);
			plain_total += ns[0];
			simhost_total += ns[1];
		}
		plain_sum = plain::boxes_checksum(w);
		simhost_sum = simhost_checksum(p, sim);
		same = same && plain_sum == simhost_sum;
		p->destroy(sim);
		plain::boxes_destroy(w);
	}

	double pm = median(plain_ns), sm = median(simhost_ns);
	printf("steps=%ld\nblock=%ld\nrounds=%ld\n", o.steps, o.block, o.rounds);
	printf("plain_step_ns_median=%.0f\nsimhost_step_ns_median=%.0f\n", pm, sm);
	printf("plain_step_us_median=%.1f\nsimhost_step_us_median=%.1f\n", pm / 1e3, sm / 1e3);
	printf("ratio=%.4f\n", sm / pm);
	// The median of the ratios of paired blocks (same indices, adjacent in
	// time) and of the totals: less sensitive to how costs spread over a
	// round than the ratio of the medians.
	printf("ratio_paired_median=%.4f\nratio_total=%.4f\n", median(pair_ratio), simhost_total / plain_total);
	printf("plain_checksum=%016" PRIx64 "\nsimhost_checksum=%016" PRIx64 "\nsame_state=%d\n", plain_sum,
	       simhost_sum, same ? 1 : 0);
	dCloseODE();
	return same ? 0 : 1;
}
