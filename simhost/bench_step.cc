// Benchmark: the wall-clock cost of one step of the built-in models, as
// min / median / max over many steps, through the plug-in ABI. For 1000
// boxes this is the variable cost of the TCS paper's Figure 1. Then the
// robot model (robot/ode_robot.h) against the built-in double pendulum,
// 10,000 steps each through Model::step: the same double pendulum built
// from a description, and a 3-link chain. Prints figures; judges nothing.
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

#include "description.h"
#include "model.h"
#include "ode_init.h"
#include "ode_robot.h"
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

namespace r = tcs::sim::robot;

// A uniform rod of `length` along z hanging from `top` (x-z plane), its
// inertia as the built-in models' thin_rod_mass gives it.
r::Link rod(const char *name, double mass, double length, double top)
{
	r::Link l;
	l.name = name;
	l.pose.p = { 0, 0, top };
	l.mass = mass;
	l.inertial.p = { 0, 0, top - length / 2 };
	double perp = mass * length * length / 12, rr = 0.01 * length;
	l.inertia = { perp, perp, mass * rr * rr / 2, 0, 0, 0 };
	return l;
}

r::Joint hinge(const char *name, const char *parent, const char *child, double at, r::Vec3 axis)
{
	r::Joint j;
	j.name = name;
	j.kind = r::Joint::Kind::continuous;
	j.parent = parent;
	j.child = child;
	j.pose.p = { 0, 0, at };
	j.axis = axis;
	return j;
}

// n rods of 1 m and 1 kg on hinges; the axes alternate y, x from the
// third on (the double pendulum's two are both about -y, as the
// built-in's).
r::Model rods(int n)
{
	const char *links[] = { "link1", "link2", "link3" }, *joints[] = { "shoulder", "elbow", "wrist" };
	r::Model m;
	m.name = "rods";
	for (int i = 0; i < n; i++) {
		m.links.push_back(rod(links[i], 1, 1, -i));
		m.joints.push_back(hinge(joints[i], i ? links[i - 1] : "world", links[i], -i,
					 i < 2 ? r::Vec3{ 0, -1, 0 } : r::Vec3{ 1, 0, 0 }));
	}
	return m;
}

int bench_direct(const char *label, tcs::Result<std::unique_ptr<tcs::sim::Model>> made, double &median)
{
	if (!made) {
		fprintf(stderr, "%s: %s\n", label, made.error().message.c_str());
		return 1;
	}
	tcs::sim::Model &m = **made;
	const int steps = 10000;
	std::vector<double> ns;
	ns.reserve(steps);
	double t_all = now_ns();
	for (int i = 0; i < steps; i++) {
		double t0 = now_ns();
		if (auto s = m.step(1e-3); !s) {
			fprintf(stderr, "%s: %s\n", label, s.error().message.c_str());
			return 1;
		}
		ns.push_back(now_ns() - t0);
	}
	t_all = now_ns() - t_all;
	std::sort(ns.begin(), ns.end());
	median = ns[ns.size() / 2];
	printf("%-28s %d steps in %7.2f ms; per step: min %7.0f  median %7.0f  max %8.0f ns\n", label, steps,
	       t_all * 1e-6, ns.front(), median, ns.back());
	return 0;
}

int bench_robot()
{
	if (auto s = tcs::sim::ode_ready(); !s) {
		fprintf(stderr, "%s\n", s.error().message.c_str());
		return 1;
	}
	printf("\nrobot model vs built-in, through Model::step:\n");
	const char *keys[] = { "initial_angle1" };
	const double values[] = { 1.0 };
	struct tcs_sim_model spec = { "d", "double_pendulum", keys, values, 1 };
	auto params = tcs::sim::Params::parse("double_pendulum 'd'", tcs::sim::double_pendulum_model.params, spec);
	if (!params) {
		fprintf(stderr, "%s\n", params.error().message.c_str());
		return 1;
	}
	double builtin = 0, two = 0, three = 0;
	int r = bench_direct("double_pendulum (built-in)", tcs::sim::double_pendulum_model.make("d", *params), builtin);
	tcs::sim::RobotOptions o;
	o.initial_positions["shoulder"] = 1.0;
	r |= bench_direct("double pendulum (robot)", tcs::sim::make_robot_model("p", rods(2), o), two);
	r |= bench_direct("3-link chain (robot)", tcs::sim::make_robot_model("c", rods(3), o), three);
	if (r == 0)
		printf("median ratios to the built-in: robot double pendulum %.2f, 3-link chain %.2f\n", two / builtin,
		       three / builtin);
	return r;
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
	r |= bench_robot();
	return r;
}
