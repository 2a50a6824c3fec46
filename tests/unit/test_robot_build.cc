// Unit tests for building robot models (ode_robot.h): initial positions
// and velocities and the scenario's pose, the signal table, refusals of
// what ODE cannot take (each naming the culprit), and a 10,000-link chain.
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

void test_initial_state(void **)
{
	RobotOptions o;
	o.initial_positions = { { "j1", 0.4 }, { "j2", -0.7 }, { "j3", 2.5 } };
	o.initial_velocities = { { "j1", 1.5 }, { "j2", -0.5 }, { "j3", 0.25 } };
	Bot bot(chain3(), o);
	for (const auto &[j, v] : o.initial_positions)
		expect_near(bot.get(j + ".position"), v, 1e-12, "initial position");
	for (const auto &[j, v] : o.initial_velocities)
		expect_near(bot.get(j + ".velocity"), v, 1e-12, "initial velocity");
	// The first link's pose follows from j1 alone: turned 0.4 about y.
	std::vector<double> p = bot.values("l1.pose");
	r::Quat want = axis_angle({ 0, 1, 0 }, 0.4);
	for (int i = 0; i < 4; i++)
		expect_near(p[3 + i], want[i], 1e-12, "l1 orientation");
	// A step later the joints are where their velocities took them.
	bot.step();
	expect_near(bot.get("j1.position"), 0.4 + 1.5 * dt, 0.1 * dt, "moved");

	// A prismatic joint, and the scenario's pose of the root.
	r::Model m;
	m.name = "lift";
	m.links.push_back(box_link("base", 1.0, { 0.2, 0.2, 0.2 }, pose(0, 0, 0), { 0, 0, 0 }));
	m.links.push_back(box_link("carriage", 1.0, { 0.2, 0.2, 0.2 }, pose(0, 0, 0.5), { 0, 0, 0.5 }));
	m.joints.push_back(joint("slide", K::prismatic, "base", "carriage", pose(0, 0, 0.5), { 1, 0, 0 }));
	RobotOptions lo;
	lo.fixed = true;
	lo.pose = pose(3, 4, 5, axis_angle({ 0, 0, 1 }, M_PI / 2));
	lo.initial_positions["slide"] = 0.25;
	lo.initial_velocities["slide"] = -0.1;
	Bot lift(m, lo);
	expect_near(lift.get("slide.position"), 0.25, 1e-12, "slider position");
	expect_near(lift.get("slide.velocity"), -0.1, 1e-12, "slider velocity");
	// The model turned 90 degrees about z: its x is the world's y.
	p = lift.values("carriage.pose");
	expect_near(p[0], 3, 1e-12, "carriage x");
	expect_near(p[1], 4.25, 1e-12, "carriage y");
	expect_near(p[2], 5.5, 1e-12, "carriage z");
}

void test_signals(void **)
{
	r::Model m = chain3();
	m.joints[1].kind = K::fixed;
	m.sensors.push_back(sensor("imu", S::imu, "l3", pose(0, 0, -1)));
	Bot bot(m);
	std::vector<std::string> want = { "r.j1.position",
					  "r.j1.velocity",
					  "r.j1.effort",
					  "r.j3.position",
					  "r.j3.velocity",
					  "r.j3.effort",
					  "r.l1.pose",
					  "r.l1.twist",
					  "r.l2.pose",
					  "r.l2.twist",
					  "r.l3.pose",
					  "r.l3.twist",
					  "r.imu.orientation",
					  "r.imu.angular_velocity",
					  "r.imu.linear_acceleration" };
	assert_int_equal(bot.signals().size(), want.size());
	for (size_t i = 0; i < want.size(); i++)
		assert_string_equal(bot.signals()[i].name.c_str(), want[i].c_str());
	assert_true(bot.signals()[2].flags & TCS_SIM_SIGNAL_WRITABLE);
	assert_false(bot.signals()[0].flags & TCS_SIM_SIGNAL_WRITABLE);
}

void test_static_model(void **)
{
	// A static model: every link stays where the description puts it
	// (moved by the scenario's pose), with no joint signals.
	r::Model m = chain3();
	m.is_static = true;
	m.links[1].mass = 0; // a static link needs none
	RobotOptions o;
	o.pose = pose(1, 2, 3);
	Bot bot(m, o);
	assert_int_equal(bot.signals().size(), 6);
	bot.step(100);
	std::vector<double> p = bot.values("l3.pose");
	expect_near(p[0], 1, 0, "x");
	expect_near(p[1], 2, 0, "y");
	expect_near(p[2], 3 - 1.0, 0, "z");
	for (double v : bot.values("l2.twist"))
		expect_near(v, 0, 0, "at rest");
}

void test_refusals(void **)
{
	RobotOptions o;
	o.initial_positions["elbow"] = 0.1;
	std::string e = refusal(chain3(), o);
	expect_contains(e, "'elbow'");
	expect_contains(e, "j1, j2, j3");
	o = {};
	o.initial_velocities["nope"] = 0.1;
	expect_contains(refusal(chain3(), o), "'nope'");

	r::Model m = chain3();
	m.links[1].mass = 0;
	m.links[1].where = { "arm.urdf", 12 };
	e = refusal(m);
	expect_contains(e, "arm.urdf:12: link 'l2'");
	expect_contains(e, "mass");
	m = chain3();
	m.links[2].mass = NAN;
	expect_contains(refusal(m), "link 'l3'");
	m = chain3();
	m.links[0].inertia = { 1, 1, 1, 2, 0, 0 }; // ixy too large: indefinite
	e = refusal(m);
	expect_contains(e, "link 'l1'");
	expect_contains(e, "positive definite");
	m = chain3();
	m.links[0].inertia = { 1, -1, 1, 0, 0, 0 };
	expect_contains(refusal(m), "link 'l1'");
	// A welded link needs no valid mass.
	m = chain3();
	m.links[0].mass = 0;
	m.joints[0].kind = K::fixed;
	Bot ok(m);

	m = chain3();
	m.joints[1].parent = "nowhere";
	expect_contains(refusal(m), "'nowhere'");
	m = chain3();
	m.joints[0].kind = K::revolute;
	m.joints[0].lower = -4;
	m.joints[0].upper = 1;
	expect_contains(refusal(m), "joint 'j1'");
	m = floor_and_mast();
	expect_contains(refusal(m), "plane"); // not fixed: the plane would move
	m = chain3();
	m.joints.push_back(joint("weld", K::fixed, "world", "l2", pose(0, 0, -0.5)));
	expect_contains(refusal(m), "joint 'j2' moves link 'l2'");
}

void test_long_chain(void **)
{
	const size_t n = 10000;
	r::Model m;
	m.name = "rope";
	m.links.reserve(n);
	m.joints.reserve(n);
	for (size_t i = 0; i < n; i++) {
		std::string name = "l" + std::to_string(i);
		double top = -0.01 * (double)i;
		r::Link l = box_link("", 0.01, { 0.005, 0.005, 0.01 }, pose(0, 0, top), { 0, 0, top - 0.005 });
		l.name = name;
		m.links.push_back(l);
		r::Joint j = joint("", K::continuous, i ? m.links[i - 1].name.c_str() : "world", "", pose(0, 0, top));
		j.name = "j" + std::to_string(i);
		j.child = name;
		m.joints.push_back(j);
	}
	RobotOptions o;
	o.initial_positions["j0"] = 0.3;
	double t0 = now_s();
	auto model = MUST(tcs::sim::make_robot_model("rope", m, o));
	double built = now_s() - t0;
	std::vector<tcs::sim::SignalDesc> d;
	model->describe(d);
	assert_int_equal(d.size(), 3 * n + 2 * n);
	t0 = now_s();
	const int steps = 20;
	for (int i = 0; i < steps; i++)
		CHECK_OK(model->step(dt));
	double stepped = (now_s() - t0) / steps;
	print_message("%zu-link chain: built in %.3f s, %.2f ms a step (QuickStep), %zu signals\n", n, built,
		      stepped * 1e3, d.size());
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_initial_state), cmocka_unit_test(test_signals),
		cmocka_unit_test(test_static_model),  cmocka_unit_test(test_refusals),
		cmocka_unit_test(test_long_chain),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
