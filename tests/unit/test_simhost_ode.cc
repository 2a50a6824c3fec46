// Unit tests for the built-in ODE simulation plug-in, through its C ABI
// only (as the coordinator and any other host see it): the signal table,
// the physics of each model against closed-form results, zero-order hold of
// efforts, error messages, independence of models in one world, and the
// determinism of the boxes workload.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "tcs/simhost.h"

namespace {

constexpr double g = 9.81;
constexpr int64_t kMs = 1000000;

const struct tcs_simhost_plugin *ode()
{
	return tcs_simhost_ode_plugin();
}

struct Param {
	const char *key;
	double value;
};

// One model's description, kept alive for create().
struct Spec {
	const char *name;
	const char *type;
	std::vector<const char *> keys;
	std::vector<double> values;

	Spec(const char *n, const char *t, std::initializer_list<Param> ps = {}) : name(n), type(t)
	{
		for (const Param &p : ps) {
			keys.push_back(p.key);
			values.push_back(p.value);
		}
	}
	struct tcs_sim_model model() const
	{
		return { name, type, keys.data(), values.data(), keys.size() };
	}
};

// A world, destroyed at scope end; lookups by name fail the test when the
// signal does not exist.
class Sim {
public:
	explicit Sim(std::initializer_list<Spec> specs, int64_t step_ns = kMs)
	{
		std::vector<struct tcs_sim_model> ms;
		for (const Spec &s : specs)
			ms.push_back(s.model());
		char err[256] = "";
		sim_ = ode()->create(ms.data(), ms.size(), step_ns, err, sizeof err);
		if (!sim_) {
			print_error("create failed: %s\n", err);
			fail();
		}
	}
	~Sim() { ode()->destroy(sim_); }
	Sim(const Sim &) = delete;
	Sim &operator=(const Sim &) = delete;

	tcs_sim *get() const { return sim_; }

	size_t index(const char *name) const
	{
		for (size_t i = 0; i < ode()->signal_count(sim_); i++)
			if (strcmp(ode()->signal_info(sim_, i)->name, name) == 0)
				return i;
		print_error("no signal %s\n", name);
		fail();
		return 0;
	}
	double get(const char *name) const
	{
		double v[7];
		assert_int_equal(ode()->read(sim_, index(name), v), 0);
		return v[0];
	}
	std::vector<double> values(const char *name) const
	{
		size_t i = index(name);
		std::vector<double> v(ode()->signal_info(sim_, i)->width);
		assert_int_equal(ode()->read(sim_, i, v.data()), 0);
		return v;
	}
	int set(const char *name, double v) { return ode()->write(sim_, index(name), &v); }
	void step(int n = 1)
	{
		char err[256] = "";
		for (int i = 0; i < n; i++) {
			if (ode()->step(sim_, err, sizeof err) != 0) {
				print_error("step failed: %s\n", err);
				fail();
			}
		}
	}

private:
	tcs_sim *sim_;
};

// create()'s message for a world that must be refused (NULL and a reason).
std::string create_error(std::initializer_list<Spec> specs, int64_t step_ns = kMs)
{
	std::vector<struct tcs_sim_model> ms;
	for (const Spec &s : specs)
		ms.push_back(s.model());
	char err[256] = "";
	tcs_sim *sim = ode()->create(ms.data(), ms.size(), step_ns, err, sizeof err);
	if (sim) {
		ode()->destroy(sim);
		print_error("create succeeded, expected an error\n");
		fail();
	}
	assert_true(err[0] != 0);
	assert_null(strchr(err, '\n')); // one line: the caller adds file:line
	return err;
}

void expect_contains(const std::string &text, const char *part)
{
	if (text.find(part) == std::string::npos) {
		print_error("'%s' does not contain '%s'\n", text.c_str(), part);
		fail();
	}
}

// The rod's energy with the hinge as the height reference.
double pendulum_energy(double angle, double rate, double m, double L)
{
	return 0.5 * (m * L * L / 3) * rate * rate - m * g * L / 2 * std::cos(angle);
}

void test_abi(void **)
{
	const struct tcs_simhost_plugin *p = ode();
	assert_non_null(p);
	assert_int_equal(p->abi_version, TCS_SIMHOST_ABI_VERSION);
	assert_string_equal(p->name, "ode");
	std::vector<std::string> types;
	for (const char *const *t = p->model_types; *t; t++)
		types.emplace_back(*t);
	assert_int_equal(types.size(), 4);
	// Every listed type exists with its defaults (boxes made small to be quick).
	for (const std::string &t : types) {
		Spec s("m", t.c_str());
		if (t == "boxes")
			s = Spec("m", "boxes", { { "count", 10 } });
		Sim sim({ s });
		assert_true(ode()->signal_count(sim.get()) > 0);
		sim.step(10);
	}
	// An empty world is a world.
	Sim none({});
	assert_int_equal(ode()->signal_count(none.get()), 0);
	none.step();
}

void test_pendulum_signals(void **)
{
	Sim sim({ Spec("pendulum", "pendulum") });
	struct {
		const char *name;
		uint32_t width;
		bool writable;
		const char *unit;
	} want[] = {
		{ "pendulum.hinge.position", 1, false, "rad" },
		{ "pendulum.hinge.velocity", 1, false, "rad/s" },
		{ "pendulum.hinge.effort", 1, true, "N*m" },
		{ "pendulum.rod.pose", 7, false, nullptr },
		{ "pendulum.rod.twist", 6, false, nullptr },
	};
	assert_int_equal(ode()->signal_count(sim.get()), 5);
	for (size_t i = 0; i < 5; i++) {
		const struct tcs_sim_signal_info *si = ode()->signal_info(sim.get(), i);
		assert_non_null(si);
		assert_string_equal(si->name, want[i].name);
		assert_int_equal(si->width, want[i].width);
		assert_int_equal((si->flags & TCS_SIM_SIGNAL_WRITABLE) != 0, want[i].writable);
		assert_non_null(si->unit);
		if (want[i].unit)
			assert_string_equal(si->unit, want[i].unit);
	}
	assert_null(ode()->signal_info(sim.get(), 5));

	// Bad indices and read-only signals are refused; so is a value that
	// would poison the state.
	double v[7] = { 1 };
	assert_int_equal(ode()->read(sim.get(), 5, v), -1);
	assert_int_equal(ode()->write(sim.get(), 5, v), -1);
	assert_int_equal(ode()->write(sim.get(), 0, v), -1);
	assert_int_equal(ode()->write(sim.get(), 4, v), -1);
	assert_int_equal(sim.set("pendulum.hinge.effort", NAN), -1);
	assert_int_equal(sim.set("pendulum.hinge.effort", INFINITY), -1);
	assert_int_equal(sim.set("pendulum.hinge.effort", 0.5), 0);

	// At rest, hanging: the centre of mass L/2 below the hinge, upright
	// orientation quaternion, no motion.
	std::vector<double> pose = sim.values("pendulum.rod.pose");
	assert_float_equal(pose[0], 0, 1e-12);
	assert_float_equal(pose[2], -0.5, 1e-12);
	assert_float_equal(pose[3], 1, 1e-12);
	for (double t : sim.values("pendulum.rod.twist"))
		assert_float_equal(t, 0, 1e-12);
}

// The period of small oscillations, from upward zero crossings over 20 s.
double measured_period(double L)
{
	Sim sim({ Spec("p", "pendulum", { { "length", L }, { "initial_angle", 0.05 } }) });
	std::vector<double> crossings;
	double prev = sim.get("p.hinge.position");
	for (int i = 1; i <= 20000; i++) {
		sim.step();
		double a = sim.get("p.hinge.position");
		if (prev < 0 && a >= 0)
			crossings.push_back((i - 1 + -prev / (a - prev)) * 1e-3);
		prev = a;
	}
	assert_true(crossings.size() >= 5);
	return (crossings.back() - crossings.front()) / (double)(crossings.size() - 1);
}

void test_pendulum_period(void **)
{
	for (double L : { 1.0, 0.5 }) {
		// A uniform rod's small-oscillation period, lengthened at the
		// amplitude of 0.05 rad by theta^2/16 + 11 theta^4/3072 (the
		// series of the elliptic integral). What remains is the 1 ms
		// integrator's and the crossings' interpolation, both of second
		// order in omega * dt: below (omega * dt)^2.
		const double theta = 0.05, omega = std::sqrt(3 * g / (2 * L)), dt = 1e-3;
		double want = 2 * M_PI / omega * (1 + theta * theta / 16 + 11 * std::pow(theta, 4) / 3072);
		double got = measured_period(L);
		print_message("L=%g m: period %.6f s, the rod's at 0.05 rad %.6f s, error %+.5f %%\n", L, got, want,
			      100 * (got / want - 1));
		assert_true(std::fabs(got / want - 1) < (omega * dt) * (omega * dt));
	}
}

void test_pendulum_energy(void **)
{
	Sim sim({ Spec("p", "pendulum", { { "initial_angle", 1.0 } }) });
	auto energy = [&] { return pendulum_energy(sim.get("p.hinge.position"), sim.get("p.hinge.velocity"), 1, 1); };
	double e0 = energy();
	// Measured against the swing's own energy (above the bottom), not the
	// arbitrary zero: the stricter figure.
	double swing = e0 + g / 2;
	double worst = 0;
	for (int i = 0; i < 10000; i++) {
		sim.step();
		worst = std::fmax(worst, std::fabs(energy() - e0));
		// The link's pose agrees with the joint's angle (up to the
		// hinge's small constraint drift, which ODE corrects each step).
		if (i % 1000 == 0) {
			std::vector<double> pose = sim.values("p.rod.pose");
			double a = sim.get("p.hinge.position");
			assert_float_equal(pose[0], 0.5 * std::sin(a), 1e-4);
			assert_float_equal(pose[2], -0.5 * std::cos(a), 1e-4);
		}
	}
	print_message("energy: worst deviation over 10 s %.4f %% of the swing energy\n", 100 * worst / swing);
	assert_true(worst / swing < 0.005);
}

void test_pendulum_effort(void **)
{
	Sim sim({ Spec("p", "pendulum") });
	assert_int_equal(sim.set("p.hinge.effort", 2.0), 0);
	// Zero-order hold: the effort takes effect from the next step, and
	// reads back as what was in force during the last step.
	assert_float_equal(sim.get("p.hinge.effort"), 0, 0);
	assert_float_equal(sim.get("p.hinge.position"), 0, 0);
	sim.step(100);
	assert_float_equal(sim.get("p.hinge.effort"), 2.0, 0);
	assert_true(sim.get("p.hinge.position") > 0.01);
	assert_true(sim.get("p.hinge.velocity") > 0);

	Sim neg({ Spec("p", "pendulum") });
	neg.set("p.hinge.effort", -2.0);
	neg.step(100);
	assert_true(neg.get("p.hinge.position") < -0.01);
}

void test_pendulum_static_balance(void **)
{
	const double m = 1.5, L = 0.8;
	for (double a : { 0.3, 1.0, -0.7 }) {
		Sim sim({ Spec("p", "pendulum", { { "mass", m }, { "length", L }, { "initial_angle", a } }) });
		sim.set("p.hinge.effort", m * g * L / 2 * std::sin(a));
		sim.step(5000);
		assert_float_equal(sim.get("p.hinge.position"), a, 0.01);
	}
}

void test_pendulum_damping(void **)
{
	Sim sim({ Spec("p", "pendulum", { { "initial_angle", 1.0 }, { "damping", 0.2 } }) });
	double e0 = pendulum_energy(1.0, 0, 1, 1) + g / 2;
	double last = e0;
	for (int s = 0; s < 5; s++) {
		sim.step(2000);
		double e = pendulum_energy(sim.get("p.hinge.position"), sim.get("p.hinge.velocity"), 1, 1) + g / 2;
		assert_true(e < last);
		last = e;
	}
	assert_true(last < 0.05 * e0);
	// Damping is the joint's own: the effort reads only what was commanded.
	assert_float_equal(sim.get("p.hinge.effort"), 0, 0);
}

void test_pendulum_continuous_angle(void **)
{
	// Enough speed to go over the top, again and again.
	Sim sim({ Spec("p", "pendulum", { { "initial_velocity", 12.0 } }) });
	double prev = sim.get("p.hinge.position");
	for (int i = 0; i < 3000; i++) {
		sim.step();
		double a = sim.get("p.hinge.position");
		assert_true(a > prev);
		prev = a;
	}
	assert_true(prev > 4 * M_PI);

	// An initial angle past pi is kept as given, not wrapped.
	Sim wound({ Spec("p", "pendulum", { { "initial_angle", 2 * M_PI + 0.5 } }) });
	assert_float_equal(wound.get("p.hinge.position"), 2 * M_PI + 0.5, 1e-12);
	wound.step(10);
	assert_float_equal(wound.get("p.hinge.position"), 2 * M_PI + 0.5, 0.01);
}

void test_errors(void **)
{
	std::string e = create_error({ Spec("p", "pendulm") });
	expect_contains(e, "'pendulm'");
	expect_contains(e, "pendulum, cartpole, double_pendulum, boxes");

	e = create_error({ Spec("p", "pendulum", { { "lenght", 1 } }) });
	expect_contains(e, "pendulum");
	expect_contains(e, "'lenght'");
	expect_contains(e, "length, mass, damping, initial_angle, initial_velocity");

	e = create_error({ Spec("p", "pendulum", { { "length", -1 } }) });
	expect_contains(e, "'length'");
	expect_contains(e, "> 0");
	expect_contains(create_error({ Spec("p", "pendulum", { { "mass", 0 } }) }), "'mass'");
	expect_contains(create_error({ Spec("p", "pendulum", { { "damping", -0.1 } }) }), "'damping'");
	expect_contains(create_error({ Spec("p", "pendulum", { { "initial_angle", NAN } }) }), "'initial_angle'");
	expect_contains(create_error({ Spec("p", "pendulum", { { "mass", 1 }, { "mass", 2 } }) }), "twice");
	expect_contains(create_error({ Spec("b", "boxes", { { "count", 0 } }) }), "'count'");
	expect_contains(create_error({ Spec("b", "boxes", { { "count", 1.5 } }) }), "'count'");
	expect_contains(create_error({ Spec("b", "boxes", { { "seed", -1 } }) }), "'seed'");
	expect_contains(create_error({ Spec("b", "boxes", { { "arena_size", 0.5 } }) }), "do not fit");
	expect_contains(create_error({ Spec("c", "cartpole", { { "track_limit", 0 } }) }), "'track_limit'");
	expect_contains(create_error({ Spec("d", "double_pendulum", { { "length3", 1 } }) }), "'length3'");

	// The model's name is in the message too: several may share a type.
	expect_contains(create_error({ Spec("left", "pendulum"), Spec("right", "pendulum", { { "mass", -2 } }) }),
			"'right'");
	expect_contains(create_error({ Spec("p", "pendulum"), Spec("p", "cartpole") }), "same name");
	expect_contains(create_error({ Spec("a.b", "pendulum") }), "name");
	expect_contains(create_error({ Spec("", "pendulum") }), "name");
	expect_contains(create_error({ Spec("p", "pendulum") }, 0), "step");

	// A short buffer gets a truncated, terminated message.
	Spec bad("p", "pendulum", { { "lenght", 1 } });
	struct tcs_sim_model m = bad.model();
	char small[8];
	memset(small, 'x', sizeof small);
	assert_null(ode()->create(&m, 1, kMs, small, sizeof small));
	assert_int_equal(strlen(small), sizeof small - 1);
	assert_null(ode()->create(&m, 1, kMs, nullptr, 0));
}

void test_two_pendulums(void **)
{
	Sim both({ Spec("left", "pendulum", { { "initial_angle", 0.5 } }), Spec("right", "pendulum") });
	Sim alone({ Spec("left", "pendulum", { { "initial_angle", 0.5 } }) });
	assert_int_equal(ode()->signal_count(both.get()), 10);
	// They hang from the same point, and pass through each other.
	both.set("right.hinge.effort", -1.0);
	for (int i = 0; i < 2000; i++) {
		both.step();
		alone.step();
		assert_float_equal(both.get("left.hinge.position"), alone.get("left.hinge.position"), 0);
	}
	assert_true(both.get("right.hinge.position") < -0.05);
	assert_float_equal(both.get("right.hinge.effort"), -1.0, 0);
	assert_float_equal(both.get("left.hinge.effort"), 0, 0);
}

void test_boxes(void **)
{
	Sim sim({ Spec("boxes", "boxes") });
	assert_int_equal(ode()->signal_count(sim.get()), 2001);
	assert_int_equal(ode()->signal_info(sim.get(), sim.index("boxes.box0.pose"))->width, 7);
	assert_int_equal(ode()->signal_info(sim.get(), sim.index("boxes.box999.twist"))->width, 6);
	for (size_t i = 0; i < ode()->signal_count(sim.get()); i++)
		assert_int_equal(ode()->signal_info(sim.get(), i)->flags & TCS_SIM_SIGNAL_WRITABLE, 0);
	assert_int_equal(sim.set("boxes.box0.pose", 0), -1);

	sim.step(200);
	assert_true(sim.get("boxes.arena.contacts") >= 1000);
	// The arena is 10 m square by default (0.1 m boxes covering a tenth).
	double moving = 0;
	for (int i = 0; i < 1000; i++) {
		std::string box = "boxes.box" + std::to_string(i);
		std::vector<double> p = sim.values((box + ".pose").c_str());
		assert_true(std::fabs(p[0]) <= 5.0 - 0.05 + 1e-3);
		assert_true(std::fabs(p[1]) <= 5.0 - 0.05 + 1e-3);
		assert_true(p[2] > 0 && p[2] < 0.5);
		std::vector<double> t = sim.values((box + ".twist").c_str());
		moving += std::hypot(t[0], t[1]) > 0.1;
	}
	assert_true(moving > 500); // still sliding, not settled
}

// The whole state of a boxes world, bit for bit.
std::vector<double> box_state(const Sim &sim)
{
	std::vector<double> all;
	for (size_t i = 0; i < ode()->signal_count(sim.get()); i++) {
		double v[7];
		assert_int_equal(ode()->read(sim.get(), i, v), 0);
		all.insert(all.end(), v, v + ode()->signal_info(sim.get(), i)->width);
	}
	return all;
}

void test_boxes_deterministic(void **)
{
	Spec spec("b", "boxes", { { "count", 300 }, { "seed", 7 } });
	Sim a({ spec }), b({ spec });
	Sim other({ Spec("b", "boxes", { { "count", 300 }, { "seed", 8 } }) });
	assert_true(box_state(a) == box_state(b));
	assert_true(box_state(a) != box_state(other));
	// Interleaved unevenly: each world's solver sees only its own random
	// sequence.
	a.step(50);
	other.step(20);
	b.step(20);
	other.step(20);
	b.step(30);
	a.step(150);
	b.step(150);
	assert_true(box_state(a) == box_state(b));
}

void test_cartpole(void **)
{
	Sim sim({ Spec("cp", "cartpole", { { "initial_angle", 0.1 }, { "track_limit", 0.5 } }) });
	// 0 is upright: tipped a little, it falls the way it leans.
	assert_float_equal(sim.get("cp.hinge.position"), 0.1, 1e-12);
	std::vector<double> pose = sim.values("cp.pole.pose");
	assert_float_equal(pose[0], 0.5 * std::sin(0.1), 1e-9);
	assert_float_equal(pose[2], 0.5 * std::cos(0.1), 1e-9);
	sim.step(1000);
	assert_true(sim.get("cp.hinge.position") > 1.0);

	// The slider is the motor; the hinge is passive.
	assert_int_equal(sim.set("cp.hinge.effort", 1.0), -1);
	assert_int_equal(sim.set("cp.slider.effort", 5.0), 0);
	Sim push({ Spec("cp", "cartpole") });
	push.set("cp.slider.effort", 5.0);
	push.step(200);
	assert_true(push.get("cp.slider.position") > 0.05);
	assert_true(push.get("cp.cart.pose") > 0.05);
	assert_float_equal(push.get("cp.slider.effort"), 5.0, 0);
	// Accelerating the cart to +x tips the pole back, to -x.
	assert_true(push.get("cp.hinge.position") < 0);

	// The track ends where it was told.
	sim.set("cp.slider.effort", 20.0);
	sim.step(2000);
	assert_true(sim.get("cp.slider.position") < 0.5 + 0.01);
	assert_true(sim.get("cp.slider.position") > 0.4);
}

void test_double_pendulum(void **)
{
	Sim sim({ Spec("a", "double_pendulum", { { "initial_angle1", 0.5 } }) });
	static const char *const want[] = { "a.shoulder.position", "a.shoulder.velocity", "a.shoulder.effort",
					    "a.elbow.position",	   "a.elbow.velocity",	  "a.elbow.effort",
					    "a.link1.pose",	   "a.link1.twist",	  "a.link2.pose",
					    "a.link2.twist" };
	assert_int_equal(ode()->signal_count(sim.get()), 10);
	for (size_t i = 0; i < 10; i++)
		assert_string_equal(ode()->signal_info(sim.get(), i)->name, want[i]);

	// Straight and tilted, the tip sits at 2 m from the shoulder.
	std::vector<double> p2 = sim.values("a.link2.pose");
	assert_float_equal(p2[0], 1.5 * std::sin(0.5), 1e-9);
	assert_float_equal(p2[2], -1.5 * std::cos(0.5), 1e-9);
	// It falls back towards hanging.
	sim.step(100);
	assert_true(sim.get("a.shoulder.position") < 0.5);
	assert_true(sim.get("a.shoulder.velocity") < 0);

	// Only the elbow is motorised.
	assert_int_equal(sim.set("a.shoulder.effort", 1.0), -1);
	Sim arm({ Spec("a", "double_pendulum") });
	assert_int_equal(arm.set("a.elbow.effort", 1.0), 0);
	arm.step(200);
	assert_true(arm.get("a.elbow.position") > 0.05);
	// Reaction: the upper link turns the other way.
	assert_true(arm.get("a.shoulder.position") < 0);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_abi),
		cmocka_unit_test(test_pendulum_signals),
		cmocka_unit_test(test_pendulum_period),
		cmocka_unit_test(test_pendulum_energy),
		cmocka_unit_test(test_pendulum_effort),
		cmocka_unit_test(test_pendulum_static_balance),
		cmocka_unit_test(test_pendulum_damping),
		cmocka_unit_test(test_pendulum_continuous_angle),
		cmocka_unit_test(test_errors),
		cmocka_unit_test(test_two_pendulums),
		cmocka_unit_test(test_boxes),
		cmocka_unit_test(test_boxes_deterministic),
		cmocka_unit_test(test_cartpole),
		cmocka_unit_test(test_double_pendulum),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
