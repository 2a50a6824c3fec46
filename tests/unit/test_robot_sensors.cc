// Unit tests for the robot model's sensors (ode_robot.h) in states whose
// readings are known: IMUs at rest, falling and spinning, force-torque on
// a weld and on a motor, rays above a plane, a box resting on a plane,
// and Gazebo's self-collision rule.
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

void test_imu_at_rest(void **)
{
	const double tilt = 0.5;
	r::Model m;
	m.name = "base";
	m.links.push_back(box_link("base", 5.0, { 0.4, 0.4, 0.1 }, pose(0, 0, 0), { 0, 0, 0 }));
	// A pendulum at rest at its bottom: a moving body, held by its joint.
	m.links.push_back(box_link("bob", 1.0, { 0.1, 0.1, 0.1 }, pose(0, 0, -0.5), { 0, 0, -0.5 }));
	m.joints.push_back(joint("hinge", K::revolute, "base", "bob", pose(0, 0, 0), { 0, 1, 0 }));
	m.sensors.push_back(sensor("upright", S::imu, "base", pose(0.1, 0, 0)));
	m.sensors.push_back(sensor("tilted", S::imu, "base", pose(0, 0.1, 0, axis_angle({ 1, 0, 0 }, tilt))));
	m.sensors.push_back(sensor("hanging", S::imu, "bob", pose(0, 0, -0.5, axis_angle({ 1, 0, 0 }, tilt))));
	RobotOptions o;
	o.fixed = true;
	Bot bot(m, o);
	bot.step(500);
	std::vector<double> a = bot.values("upright.linear_acceleration");
	expect_near(a[0], 0, 1e-9, "upright x");
	expect_near(a[1], 0, 1e-9, "upright y");
	expect_near(a[2], g, 1e-9, "upright z");
	// Turned by `tilt` about x: +g up reads (0, g sin, g cos).
	for (const char *s : { "tilted.linear_acceleration", "hanging.linear_acceleration" }) {
		a = bot.values(s);
		print_message("%s: %.6f %.6f %.6f\n", s, a[0], a[1], a[2]);
		expect_near(a[0], 0, 1e-6, "tilted x");
		expect_near(a[1], g * std::sin(tilt), 1e-6, "tilted y");
		expect_near(a[2], g * std::cos(tilt), 1e-6, "tilted z");
	}
	std::vector<double> q = bot.values("tilted.orientation");
	expect_near(q[0], std::cos(tilt / 2), 1e-12, "orientation w");
	expect_near(q[1], std::sin(tilt / 2), 1e-12, "orientation x");
}

void test_imu_free_fall_and_spin(void **)
{
	{
		// A free body falling: an accelerometer reads nothing.
		r::Model m;
		m.name = "stone";
		m.links.push_back(box_link("stone", 1.0, { 0.1, 0.1, 0.1 }, pose(0, 0, 10), { 0, 0, 10 }));
		m.sensors.push_back(sensor("imu", S::imu, "stone", pose(0, 0, 10)));
		Bot bot(m);
		bot.step(100);
		std::vector<double> a = bot.values("imu.linear_acceleration");
		for (int i = 0; i < 3; i++)
			expect_near(a[i], 0, 1e-9, "free fall");
		expect_near(bot.values("stone.twist")[2], -g * 0.1, 1e-9, "falling speed");
	}
	// A plate spinning at w about z: an IMU at radius rad reads the
	// centripetal acceleration w^2 rad inward and g up; a turned one
	// reads the angular velocity in its own axes.
	const double w = 2.0, rad = 0.5;
	r::Model m = turntable(0, 0, 0, 0);
	m.sensors.push_back(sensor("rim", S::imu, "plate", pose(rad, 0, 0)));
	r::Quat turned = axis_angle({ 1, 1, 0 }, 0.8);
	m.sensors.push_back(sensor("turned", S::imu, "plate", pose(0, 0, 0, turned)));
	RobotOptions o;
	o.initial_velocities["spin"] = w;
	Bot bot(m, o);
	bot.step(777);
	std::vector<double> a = bot.values("rim.linear_acceleration");
	print_message("rim IMU at %.1f m, %.1f rad/s: %.6f %.6f %.6f (want %.6f 0 %.2f)\n", rad, w, a[0], a[1], a[2],
		      -w * w * rad, g);
	expect_near(a[0], -w * w * rad, 1e-3 * w * w * rad, "centripetal");
	// Differencing velocities over a step whose frame turns by w dt
	// leaves a tangential term of about w^3 rad dt / 2 (0.002 here).
	expect_near(a[1], 0, 0.6 * w * w * w * rad * dt, "tangential");
	expect_near(a[2], g, 1e-9, "vertical");
	std::vector<double> gyro = bot.values("turned.angular_velocity");
	r::Vec3 want = r::unrotate(turned, { 0, 0, w });
	for (int i = 0; i < 3; i++)
		expect_near(gyro[i], want[i], 1e-9, "angular velocity in the sensor frame");
}

void test_force_torque(void **)
{
	// An arm welded to a fixed base, its centre of mass d out along the
	// arm: the weld holds m g up and the moment m g d, about the weld,
	// against gravity's (the arm's link frame turned by 90 degrees about
	// z, so the readings turn with it).
	const double mass = 2.5, d = 0.4;
	r::Quat yaw = axis_angle({ 0, 0, 1 }, M_PI / 2);
	r::Model m;
	m.name = "bracket";
	m.links.push_back(box_link("base", 5.0, { 0.4, 0.4, 0.1 }, pose(0, 0, 0), { 0, 0, 0 }));
	m.links.push_back(box_link("arm", mass, { 0.8, 0.05, 0.05 }, pose(0, 0, 0, yaw), { d, 0, 0 }));
	m.joints.push_back(joint("mount", K::fixed, "base", "arm", pose(0, 0, 0)));
	r::Sensor ft = sensor("ft", S::force_torque, "arm", pose(0, 0, 0));
	ft.joint = "mount";
	m.sensors.push_back(ft);
	RobotOptions o;
	o.fixed = true;
	Bot bot(m, o);
	bot.step(200);
	// In the world: force (0, 0, m g); torque about the weld = -(r x m g
	// down) = (0, -m g d, 0). In the arm's frame (turned 90 degrees about
	// z) the arm's x is the world's y: torque (-m g d, 0, 0).
	std::vector<double> f = bot.values("ft.force"), t = bot.values("ft.torque");
	print_message("force-torque: force %.6f %.6f %.6f N (m g = %.6f), torque %.6f %.6f %.6f N*m (m g d = %.6f)\n",
		      f[0], f[1], f[2], mass * g, t[0], t[1], t[2], mass * g * d);
	expect_near(f[0], 0, 1e-6, "force x");
	expect_near(f[1], 0, 1e-6, "force y");
	expect_near(f[2], mass * g, 1e-6 * mass * g, "force z");
	expect_near(t[0], -mass * g * d, 1e-6 * mass * g * d, "torque x (the world's y)");
	expect_near(t[1], 0, 1e-6, "torque y");
	expect_near(t[2], 0, 1e-6, "torque z");
}

void test_force_torque_motor(void **)
{
	// A hinge holding an arm level with its effort: the joint exerts the
	// moment that holds the arm whether its constraint or its actuator
	// supplies it, so the sensor reads the effort about the axis.
	const double mass = 1.0, d = 0.3;
	r::Model m = stopped_arm(-3, 3);
	m.joints[0].lower = m.joints[0].upper = std::nullopt;
	r::Sensor ft = sensor("ft", S::force_torque, "arm", pose(0, 0, 0));
	ft.joint = "hinge";
	m.sensors.push_back(ft);
	Bot bot(m);
	// Gravity's moment about +y on the arm along +x is +m g d (it turns
	// it to positive angles); the effort cancels it.
	bot.set("hinge.effort", -mass * g * d);
	bot.step(100);
	expect_near(bot.get("hinge.velocity"), 0, 1e-9, "held level");
	std::vector<double> t = bot.values("ft.torque");
	expect_near(t[1], -mass * g * d, 1e-6, "torque about the axis");
	expect_near(bot.values("ft.force")[2], mass * g, 1e-6, "force up");
}

void test_ray(void **)
{
	r::Model m = floor_and_mast();
	// x along -z: turned +90 degrees about y.
	r::Sensor down = sensor("down", S::ray, "mast", pose(0.2, 0, 0.7, axis_angle({ 0, 1, 0 }, M_PI / 2)));
	down.range_min = 0.05;
	down.range_max = 5;
	m.sensors.push_back(down);
	// Slanted 60 degrees from the vertical: reads 0.7 / cos 60.
	r::Sensor slant =
		sensor("slant", S::ray, "mast", pose(0, 0, 0.7, axis_angle({ 0, 1, 0 }, M_PI / 2 - M_PI / 3)));
	slant.range_max = 5;
	m.sensors.push_back(slant);
	r::Sensor up = sensor("up", S::ray, "mast", pose(0, 0, 0.7, axis_angle({ 0, 1, 0 }, -M_PI / 2)));
	up.range_max = 3;
	m.sensors.push_back(up);
	RobotOptions o;
	o.fixed = true;
	Bot bot(m, o);
	bot.step();
	expect_near(bot.get("down.range"), 0.7, 1e-9, "height above the plane");
	expect_near(bot.get("slant.range"), 1.4, 1e-9, "slanted");
	expect_near(bot.get("up.range"), 3, 0, "nothing hit: range_max");
}

// A cube of edge 2h as a triangle mesh, each triangle wound
// counter-clockwise seen from outside (ODE takes the normal from it).
r::Shape cube_mesh(double h)
{
	r::Shape s;
	s.kind = r::Shape::Kind::mesh;
	s.mesh_uri = "cube";
	for (int i = 0; i < 8; i++)
		s.vertices.push_back({ i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h });
	for (int axis = 0; axis < 3; axis++)
		for (int side = 0; side < 2; side++) {
			// The face's four corners, in order around it.
			int a = 1 << ((axis + 1) % 3), b = 1 << ((axis + 2) % 3), f = side ? 1 << axis : 0;
			unsigned q[4] = { (unsigned)f, (unsigned)(f | a), (unsigned)(f | a | b), (unsigned)(f | b) };
			r::Vec3 n{ 0, 0, 0 };
			n[axis] = side ? 1 : -1;
			r::Vec3 e1 = r::sub(s.vertices[q[1]], s.vertices[q[0]]),
				e2 = r::sub(s.vertices[q[2]], s.vertices[q[0]]);
			if (r::dot(r::cross(e1, e2), n) < 0)
				std::swap(q[1], q[3]);
			s.indices.insert(s.indices.end(), { q[0], q[1], q[2], q[0], q[2], q[3] });
		}
	return s;
}

void test_contact(void **)
{
	// Each shape resting on the floor plane: the contact sensor reads its
	// weight, up, and it rests at the height its shape gives.
	const double mass = 2.0;
	struct Case {
		const char *what;
		r::Shape shape;
		r::Quat turn;
		double rest; // the centre's height at rest
	} cases[5];
	cases[0] = { "box", {}, { 1, 0, 0, 0 }, 0.1 };
	cases[0].shape.kind = r::Shape::Kind::box;
	cases[0].shape.size = { 0.2, 0.3, 0.2 };
	cases[1] = { "sphere", {}, { 1, 0, 0, 0 }, 0.15 };
	cases[1].shape.kind = r::Shape::Kind::sphere;
	cases[1].shape.radius = 0.15;
	cases[2] = { "cylinder (upright)", {}, { 1, 0, 0, 0 }, 0.2 };
	cases[2].shape.kind = r::Shape::Kind::cylinder;
	cases[2].shape.radius = 0.1;
	cases[2].shape.length = 0.4;
	cases[3] = { "capsule (lying)", {}, axis_angle({ 1, 0, 0 }, M_PI / 2), 0.08 };
	cases[3].shape.kind = r::Shape::Kind::capsule;
	cases[3].shape.radius = 0.08;
	cases[3].shape.length = 0.3;
	cases[4] = { "mesh (cube)", cube_mesh(0.12), { 1, 0, 0, 0 }, 0.12 };
	for (const Case &c : cases) {
		r::Model m = floor_and_mast();
		double z = c.rest + 0.001; // dropped from a millimetre
		r::Link thing = box_link("thing", mass, { 0.2, 0.2, 0.2 }, pose(1, 0, z, c.turn), { 1, 0, z });
		r::Collision col;
		col.name = "shell";
		col.pose = pose(1, 0, z, c.turn);
		col.shape = c.shape;
		thing.collisions.push_back(col);
		thing.self_collide = true;
		m.links.push_back(thing);
		m.sensors.push_back(sensor("touch", S::contact, "thing", pose(1, 0, z)));
		m.sensors.push_back(sensor("pressed", S::contact, "floor", pose(0, 0, 0)));
		RobotOptions o;
		o.fixed = true;
		Bot bot(m, o);
		bot.step(1000);
		std::vector<double> f = bot.values("touch.force");
		double h = bot.values("thing.pose")[2];
		print_message("%-18s on the floor: %g contacts, force %.5f %.5f %.5f N (m g = %.5f), centre at %.6f m "
			      "(shape: %.6f)\n",
			      c.what, bot.get("touch.count"), f[0], f[1], f[2], mass * g, h, c.rest);
		assert_true(bot.get("touch.count") > 0);
		expect_near(f[0], 0, 1e-6, "force x");
		expect_near(f[1], 0, 1e-6, "force y");
		expect_near(f[2], mass * g, 1e-3 * mass * g, "force z");
		// The floor (welded: no body) bears the reaction.
		expect_near(bot.values("pressed.force")[2], -mass * g, 1e-3 * mass * g, "the floor's force");
		// At rest on the plane, sunk by the contacts' softness: m g
		// over their stiffness (2e7 N/m each), microns.
		expect_near(h, c.rest, 1e-5, "resting height");
		expect_near(bot.values("thing.twist")[2], 0, 1e-6, "at rest");
	}
}

void test_joined_links_never_collide(void **)
{
	// An arm hinged to a base with their shapes overlapping at the hinge,
	// both self-colliding: the joint keeps them from touching, and the
	// arm swings through as if the base were not there.
	r::Model m = floor_and_mast();
	m.links[0].collisions.push_back(box_collision("block", { 0.4, 0.4, 0.4 }, pose(0, 0, 1)));
	r::Link arm = box_link("arm", 1.0, { 0.6, 0.05, 0.05 }, pose(0, 0, 1), { 0.3, 0, 1 });
	arm.collisions.push_back(box_collision("bar", { 0.6, 0.05, 0.05 }, pose(0.3, 0, 1)));
	arm.self_collide = true;
	m.links.push_back(arm);
	m.joints.push_back(joint("hinge", K::continuous, "floor", "arm", pose(0, 0, 1), { 0, 1, 0 }));
	m.sensors.push_back(sensor("touch", S::contact, "arm", pose(0, 0, 1)));
	RobotOptions o;
	o.fixed = true;
	Bot bot(m, o);
	bot.step(300);
	assert_int_equal((int)bot.get("touch.count"), 0);
	assert_true(bot.get("hinge.position") > 1.0);
}

void test_self_collide_rule(void **)
{
	// Without self_collide on both, the crate falls through the floor.
	r::Model m = floor_and_mast();
	r::Link crate = box_link("crate", 1.0, { 0.2, 0.2, 0.2 }, pose(1, 0, 0.2), { 1, 0, 0.2 });
	crate.collisions.push_back(box_collision("shell", { 0.2, 0.2, 0.2 }, pose(1, 0, 0.2)));
	m.links.push_back(crate);
	RobotOptions o;
	o.fixed = true;
	Bot bot(m, o);
	bot.step(500);
	assert_true(bot.values("crate.pose")[2] < -0.5);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_imu_at_rest),
		cmocka_unit_test(test_imu_free_fall_and_spin),
		cmocka_unit_test(test_force_torque),
		cmocka_unit_test(test_force_torque_motor),
		cmocka_unit_test(test_ray),
		cmocka_unit_test(test_contact),
		cmocka_unit_test(test_joined_links_never_collide),
		cmocka_unit_test(test_self_collide_rule),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
