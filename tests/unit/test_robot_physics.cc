// Unit tests for the robot model's dynamics (ode_robot.h) against
// analysis, with descriptions built by hand: a compound pendulum's period
// (its inertial frame turned or not), a chain's energy, stops, the effort
// and velocity limits, damping and friction laws, a universal joint.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <ode/ode.h>

extern "C" {
#include <cmocka.h>
}

#include "frames.h"
#include "robot_checks.h"
#include "robot_models.h"

namespace {

using namespace robot_checks;
using K = r::Joint::Kind;
using S = r::Sensor::Kind;
using tcs::sim::RobotOptions;

// --- the compound pendulum ---

// A box on a hinge about y through the origin, its centre of mass d below,
// its principal moments `moments` about the axes turned by `axes` (model
// frame); the link frame itself turned by `link_q`.
r::Model compound_pendulum(double d, r::Vec3 moments, r::Quat link_q, r::Quat axes)
{
	r::Model m;
	m.name = "pendulum";
	r::Link l = box_link("bob", 2.0, { 0.1, 0.1, 0.1 }, pose(0, 0, 0, link_q), { 0, 0, -d }, axes);
	l.inertia = { moments[0], moments[1], moments[2], 0, 0, 0 };
	m.links.push_back(l);
	m.joints.push_back(joint("hinge", K::continuous, "world", "bob", pose(0, 0, 0), { 0, 1, 0 }));
	return m;
}

// The period from upward zero crossings of the hinge's angle over 20 s.
double measured_period(Bot &bot)
{
	std::vector<double> crossings;
	double prev = bot.get("hinge.position");
	for (int i = 1; i <= 20000; i++) {
		bot.step();
		double a = bot.get("hinge.position");
		if (prev < 0 && a >= 0)
			crossings.push_back((i - 1 + -prev / (a - prev)) * dt);
		prev = a;
	}
	assert_true(crossings.size() >= 5);
	return (crossings.back() - crossings.front()) / (double)(crossings.size() - 1);
}

void test_compound_pendulum_period(void **)
{
	const double m = 2.0, d = 0.3, theta = 0.05;
	const r::Vec3 moments{ 0.05, 0.02, 0.01 }; // distinct: a wrong turn of the tensor shows
	struct Case {
		const char *what;
		r::Quat link_q, axes;
	} cases[] = {
		{ "inertial frame = link frame", { 1, 0, 0, 0 }, { 1, 0, 0, 0 } },
		{ "inertial frame turned", { 1, 0, 0, 0 }, axis_angle({ 1, 2, 3 }, 0.7) },
		{ "both turned", axis_angle({ 0, 0, 1 }, 1.1), axis_angle({ -2, 1, 0.5 }, 2.0) },
	};
	for (const Case &c : cases) {
		// The moment about the hinge: the tensor's about y (the axes
		// turned by `axes` in the model frame), plus m d^2.
		r::Vec3 y = r::unrotate(c.axes, { 0, 1, 0 });
		double I = moments[0] * y[0] * y[0] + moments[1] * y[1] * y[1] + moments[2] * y[2] * y[2] + m * d * d;
		double want = 2 * M_PI * std::sqrt(I / (m * g * d)) * (1 + theta * theta / 16);
		RobotOptions o;
		o.initial_positions["hinge"] = theta;
		Bot bot(compound_pendulum(d, moments, c.link_q, c.axes), o);
		double got = measured_period(bot);
		print_message("%-28s I=%.5f kg m^2: period %.6f s, analysis %.6f s, error %+.5f %%\n", c.what, I, got,
			      want, 100 * (got / want - 1));
		assert_true(std::fabs(got / want - 1) < 0.005);
	}
}

void test_ball_pendulum(void **)
{
	// The same pendulum on a ball joint, its zero pose tilted by theta
	// about y (a ball joint takes no initial position): with y a principal
	// axis through the pivot it swings in the x-z plane, with the hinge's
	// period. Its angle comes from the link's orientation.
	const double m = 2.0, d = 0.3, theta = 0.05;
	const r::Vec3 moments{ 0.05, 0.02, 0.01 };
	r::Quat tilt = axis_angle({ 0, 1, 0 }, theta);
	r::Model desc;
	desc.name = "ball";
	r::Link l = box_link("bob", m, { 0.1, 0.1, 0.1 }, pose(0, 0, 0, tilt), r::rotate(tilt, { 0, 0, -d }), tilt);
	l.inertia = { moments[0], moments[1], moments[2], 0, 0, 0 };
	desc.links.push_back(l);
	desc.joints.push_back(joint("socket", K::ball, "world", "bob", pose(0, 0, 0)));
	Bot bot(desc);
	auto angle = [&] {
		std::vector<double> p = bot.values("bob.pose");
		expect_near(p[4], 0, 1e-9, "no turn about x");
		expect_near(p[6], 0, 1e-9, "no turn about z");
		return 2 * std::atan2(p[5], p[3]);
	};
	std::vector<double> crossings;
	double prev = angle();
	for (int i = 1; i <= 20000; i++) {
		bot.step();
		double a = angle();
		if (prev < 0 && a >= 0)
			crossings.push_back((i - 1 + -prev / (a - prev)) * dt);
		prev = a;
	}
	assert_true(crossings.size() >= 5);
	double got = (crossings.back() - crossings.front()) / (double)(crossings.size() - 1);
	double I = moments[1] + m * d * d;
	double want = 2 * M_PI * std::sqrt(I / (m * g * d)) * (1 + theta * theta / 16);
	print_message("ball joint: period %.6f s, analysis %.6f s, error %+.5f %%\n", got, want,
		      100 * (got / want - 1));
	assert_true(std::fabs(got / want - 1) < 0.005);
}

void test_gravity_off(void **)
{
	// A link with gravity off floats; its neighbour falls as the
	// integrator's free fall says: z = -g dt^2 n (n + 1) / 2 after n
	// steps (velocity first, then position).
	r::Model m;
	m.name = "pair";
	r::Link balloon = box_link("balloon", 0.1, { 0.3, 0.3, 0.3 }, pose(0, 0, 2), { 0, 0, 2 });
	balloon.gravity = false;
	m.links.push_back(balloon);
	m.links.push_back(box_link("stone", 1.0, { 0.1, 0.1, 0.1 }, pose(1, 0, 2), { 1, 0, 2 }));
	Bot bot(m);
	const int n = 500;
	bot.step(n);
	expect_near(bot.values("balloon.pose")[2], 2, 0, "floating");
	expect_near(bot.values("stone.pose")[2], 2 - g * dt * dt * n * (n + 1) / 2, 1e-12, "falling");
}

// --- a chain's energy ---

// Kinetic plus potential energy, from the pose and twist signals and the
// description's masses and inertias (inertial axes = link axes here).
double energy(const Bot &bot, const r::Model &desc)
{
	double e = 0;
	for (const r::Link &l : desc.links) {
		std::vector<double> p = bot.values(l.name + ".pose"), t = bot.values(l.name + ".twist");
		r::Quat q{ p[3], p[4], p[5], p[6] };
		r::Vec3 origin{ p[0], p[1], p[2] }, v{ t[0], t[1], t[2] }, w{ t[3], t[4], t[5] };
		r::Vec3 c = r::add(origin, r::rotate(q, r::sub(l.inertial.p, l.pose.p)));
		r::Vec3 vc = r::add(v, r::cross(w, r::sub(c, origin)));
		r::Vec3 wb = r::unrotate(q, w); // in the principal axes
		double rot = l.inertia[0] * wb[0] * wb[0] + l.inertia[1] * wb[1] * wb[1] + l.inertia[2] * wb[2] * wb[2];
		e += 0.5 * l.mass * r::dot(vc, vc) + 0.5 * rot + l.mass * g * c[2];
	}
	return e;
}

void test_chain_energy(void **)
{
	r::Model desc = chain3();
	RobotOptions o;
	o.initial_positions = { { "j1", 1.2 }, { "j2", 0.6 }, { "j3", -0.9 } };
	Bot bot(desc, o);
	double e0 = energy(bot, desc);
	// Against the swing's energy (above hanging at rest), not the
	// arbitrary zero of height: the stricter figure.
	double rest = 0;
	for (const r::Link &l : desc.links)
		rest += l.mass * g * l.inertial.p[2];
	double swing = e0 - rest, worst = 0;
	double t0 = now_s();
	for (int i = 0; i < 10000; i++) {
		bot.step();
		worst = std::fmax(worst, std::fabs(energy(bot, desc) - e0));
	}
	double took = now_s() - t0;
	print_message("3-link chain, 10 s at 1 ms: energy %.5f J (swing %.5f J), worst drift %.3g J = %.4f %% of the "
		      "swing, %.4f %% of |E|; %.2f us a step (with the energy sums)\n",
		      e0, swing, worst, 100 * worst / swing, 100 * worst / std::fabs(e0), took / 10000 * 1e6);
	assert_true(worst / swing < 0.01);
}

// --- stops ---

void test_revolute_stop(void **)
{
	// ODE finds a stop at the start of a step, so the arm may pass it by
	// at most one step's travel (v dt) before the stop's row acts; then
	// the stop's ERP (0.2) pulls it back and, at rest, holds it with the
	// world's CFM (1e-10): a residual of 1e-10 * load, nothing.
	const double upper = 0.6;
	Bot bot(stopped_arm(-1.0, upper));
	double peak = 0, vmax = 0;
	for (int i = 0; i < 2000; i++) {
		vmax = std::fmax(vmax, std::fabs(bot.get("hinge.velocity")));
		bot.step();
		peak = std::fmax(peak, bot.get("hinge.position"));
	}
	double final_pos = bot.get("hinge.position");
	print_message("revolute stop at %.3f rad: peak %.6f rad (allowed %.6f), rests at %.8f rad, |v| %.2g rad/s\n",
		      upper, peak, upper + vmax * dt, final_pos, std::fabs(bot.get("hinge.velocity")));
	assert_true(peak <= upper + vmax * dt + 1e-9);
	expect_near(final_pos, upper, 1e-6, "resting against the stop");
	expect_near(bot.get("hinge.velocity"), 0, 1e-6, "at rest");
}

void test_prismatic_stop(void **)
{
	r::Model m;
	m.name = "lift";
	m.links.push_back(box_link("carriage", 3.0, { 0.2, 0.2, 0.2 }, pose(0, 0, 1), { 0, 0, 1 }));
	r::Joint j = joint("slide", K::prismatic, "world", "carriage", pose(0, 0, 1), { 0, 0, 1 });
	j.lower = -0.2;
	j.upper = 0.5;
	m.joints.push_back(j);
	Bot bot(m);
	double low = 0, vmax = 0;
	for (int i = 0; i < 2000; i++) {
		vmax = std::fmax(vmax, std::fabs(bot.get("slide.velocity")));
		bot.step();
		low = std::fmin(low, bot.get("slide.position"));
	}
	print_message("prismatic stop at -0.2 m: lowest %.6f m (allowed %.6f), rests at %.8f m\n", low,
		      -0.2 - vmax * dt, bot.get("slide.position"));
	assert_true(low >= -0.2 - vmax * dt - 1e-9);
	expect_near(bot.get("slide.position"), -0.2, 1e-6, "resting on the stop");
	// The carriage's pose agrees: its frame 0.2 m below where it started.
	expect_near(bot.values("carriage.pose")[2], 0.8, 1e-6, "carriage height");
}

// --- effort limit, velocity limit, damping, friction ---

void test_effort_limit(void **)
{
	for (double cmd : { 10.0, -10.0 }) {
		Bot bot(turntable(2.0, 0, 0, 0));
		bot.set("spin.effort", cmd);
		bot.step(1000);
		double applied = std::copysign(2.0, cmd);
		expect_near(bot.get("spin.effort"), applied, 0, "effort applied at the limit");
		// Constant torque from rest: w = tau t / I after 1 s.
		expect_near(bot.get("spin.velocity"), applied / kTableI, 1e-6 * std::fabs(applied / kTableI),
			    "velocity under the saturated effort");
	}
	// A command within the limit passes unchanged.
	Bot bot(turntable(2.0, 0, 0, 0));
	bot.set("spin.effort", 1.5);
	bot.step();
	expect_near(bot.get("spin.effort"), 1.5, 0, "effort below the limit");
}

void test_velocity_limit(void **)
{
	// The motor stops pushing once the joint moves at its velocity limit:
	// it then exceeds it by at most one step's gain, tau dt / I.
	Bot bot(turntable(0, 1.0, 0, 0));
	bot.set("spin.effort", 2.0);
	double top = 0;
	for (int i = 0; i < 1000; i++) {
		bot.step();
		top = std::fmax(top, bot.get("spin.velocity"));
	}
	print_message("velocity limit 1 rad/s under 2 N*m: top %.6f rad/s (one step's gain %.6f)\n", top,
		      2.0 * dt / kTableI);
	assert_true(top >= 1.0 && top <= 1.0 + 2.0 * dt / kTableI + 1e-9);
}

void test_damping(void **)
{
	// I dw/dt = -c w: w(t) = w0 exp(-c t / I). The explicit damping
	// torque (from the last step's velocity) decays by (1 - c dt / I) a
	// step: 5e-4 relative from the exponential over 1 s here.
	const double c = 0.1, w0 = 3.0;
	RobotOptions o;
	o.initial_velocities["spin"] = w0;
	Bot bot(turntable(0, 0, c, 0), o);
	expect_near(bot.get("spin.velocity"), w0, 1e-12, "initial velocity");
	bot.step(1000);
	double want = w0 * std::exp(-c * 1.0 / kTableI);
	double got = bot.get("spin.velocity");
	print_message("damping %.2f N*m*s/rad: w(1 s) %.6f rad/s, exp law %.6f, error %+.4f %%\n", c, got, want,
		      100 * (got / want - 1));
	assert_true(std::fabs(got / want - 1) < 2e-3);
}

void test_friction(void **)
{
	const double f = 1.0;
	{
		// Below the friction: held still.
		Bot bot(turntable(0, 0, 0, f));
		bot.set("spin.effort", 0.6 * f);
		bot.step(1000);
		print_message("friction %.1f N*m against %.1f N*m: moved %.3g rad, v %.3g rad/s\n", f, 0.6 * f,
			      bot.get("spin.position"), bot.get("spin.velocity"));
		expect_near(bot.get("spin.position"), 0, 1e-6, "held by friction");
		expect_near(bot.get("spin.effort"), 0.6 * f, 0, "effort reads the command");
	}
	{
		// Above it: slips, accelerated by the difference.
		Bot bot(turntable(0, 0, 0, f));
		bot.set("spin.effort", 1.5 * f);
		bot.step(1000);
		double want = 0.5 * f / kTableI;
		expect_near(bot.get("spin.velocity"), want, 1e-3 * want, "slipping at (effort - friction) / I");
	}
	{
		// Spinning freely: friction decelerates at f / I until it stops.
		RobotOptions o;
		o.initial_velocities["spin"] = 2.0;
		Bot bot(turntable(0, 0, 0, f), o);
		bot.step(100);
		double want = 2.0 - f / kTableI * 0.1;
		expect_near(bot.get("spin.velocity"), want, 1e-3 * want, "decelerated by friction");
		bot.step(2000);
		expect_near(bot.get("spin.velocity"), 0, 1e-6, "stopped by friction");
	}
}

void test_universal(void **)
{
	// No gravity: an effort about the first axis turns only about it.
	r::Model m;
	m.name = "gimbal";
	m.links.push_back(box_link("head", 1.0, { 0.2, 0.2, 0.2 }, pose(0, 0, 0), { 0, 0, 0 }));
	r::Joint j = joint("gimbal", K::universal, "world", "head", pose(0, 0, 0), { 1, 0, 0 });
	j.axis2 = { 0, 1, 0 };
	m.joints.push_back(j);
	RobotOptions o;
	o.gravity = { 0, 0, 0 };
	{
		double cmd[2] = { 0.01, 0 };
		// Through the model directly: the universal's effort is 2 wide.
		auto model = MUST(tcs::sim::make_robot_model("r", m, o));
		std::vector<tcs::sim::SignalDesc> d;
		model->describe(d);
		assert_int_equal(d[2].width, 2);
		model->write(2, cmd);
		for (int i = 0; i < 100; i++)
			CHECK_OK(model->step(dt));
		double vel[2], pos[2];
		model->read(1, vel);
		model->read(0, pos);
		print_message("universal: effort (0.01, 0): velocity %.6f %.6f, position %.6f %.6f\n", vel[0], vel[1],
			      pos[0], pos[1]);
		// I = m (0.04 + 0.04) / 12 about x.
		double I = 1.0 * 0.08 / 12;
		expect_near(vel[0], 0.01 / I * 0.1, 1e-6, "about the first axis");
		expect_near(vel[1], 0, 1e-9, "not about the second");
	}
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_compound_pendulum_period),
		cmocka_unit_test(test_ball_pendulum),
		cmocka_unit_test(test_gravity_off),
		cmocka_unit_test(test_chain_energy),
		cmocka_unit_test(test_revolute_stop),
		cmocka_unit_test(test_prismatic_stop),
		cmocka_unit_test(test_effort_limit),
		cmocka_unit_test(test_velocity_limit),
		cmocka_unit_test(test_damping),
		cmocka_unit_test(test_friction),
		cmocka_unit_test(test_universal),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
