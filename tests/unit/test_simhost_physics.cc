// Unit tests for the physics of the built-in ODE plug-in's models against
// closed-form results: the pendulum's period, energy, response to effort,
// balance, damping and continuous angle (with zero-order hold of
// efforts), the cart-pole and the double pendulum.
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

#include "simhost_checks.h"
#include "tcs/simhost.h"

namespace {

using namespace simhost_checks;

// The rod's energy with the hinge as the height reference.
double pendulum_energy(double angle, double rate, double m, double L)
{
	return 0.5 * (m * L * L / 3) * rate * rate - m * g * L / 2 * std::cos(angle);
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
		cmocka_unit_test(test_pendulum_period),
		cmocka_unit_test(test_pendulum_energy),
		cmocka_unit_test(test_pendulum_effort),
		cmocka_unit_test(test_pendulum_static_balance),
		cmocka_unit_test(test_pendulum_damping),
		cmocka_unit_test(test_pendulum_continuous_angle),
		cmocka_unit_test(test_cartpole),
		cmocka_unit_test(test_double_pendulum),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
