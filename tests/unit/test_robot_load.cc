// Unit tests for simhost/robot/sdf_load: robot files read into
// descriptions. The four published files of ../shared/robots (when that
// folder is there: TCS_SHARED_ROBOTS), the project's own files in
// tests/robots (every feature, for a clone without ../shared), and the
// malformed and hostile ones (test_robot_load_bad.cc).
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

#include <cstdlib>
#include <string>
#include <sys/stat.h>

extern "C" {
#include <cmocka.h>
}

#include "missing_checks.h"
#include "robot_load_checks.h"

#ifndef TCS_TEST_ROBOTS_DIR
#error "TCS_TEST_ROBOTS_DIR must name the source tree's tests/robots folder"
#endif

int run_bad_robot_tests();

namespace {

using namespace robot_checks;
using JK = Joint::Kind;
using SK = Shape::Kind;

const double pi = 3.14159265358979323846;

std::string own(const char *name)
{
	return std::string(TCS_TEST_ROBOTS_DIR) + "/" + name;
}

// A file of ../shared/robots; absent, the case ends (missing_checks::
// missing: a skip, or a failure under CI). tests/process/test_robots.py
// says the same of it.
std::string shared(const char *name)
{
	const char *dir = getenv("TCS_SHARED_ROBOTS");
	std::string path = std::string(dir ? dir : "(TCS_SHARED_ROBOTS unset)") + "/" + name;
	struct stat st;
	if (!dir || stat(path.c_str(), &st) != 0)
		missing_checks::missing((path + " is absent").c_str(),
			"the published robot files are read from ../shared/robots beside the project: put that "
			"folder there (its SOURCES.md names each file's upstream repository and commit)");
	return path;
}

// ---- the published files -------------------------------------------------------

void test_acrobot(void **)
{
	std::string f = shared("Acrobot.urdf");
	Description d = load_ok(f);
	assert_int_equal(d.models.size(), 1);
	assert_false(d.gravity.has_value());
	const Model &m = d.models[0];
	assert_string_equal(m.name.c_str(), "Acrobot");
	assert_int_equal(m.links.size(), 3);
	assert_string_equal(m.links[0].name.c_str(), "base_link");
	// Drake's undeclared world: base_link is welded to it, massless.
	const Joint &weld = named(m.joints, "base_weld");
	assert_true(weld.kind == JK::fixed);
	assert_string_equal(weld.parent.c_str(), "world");
	assert_string_equal(weld.child.c_str(), "base_link");
	const Link &base = named(m.links, "base_link");
	near(base.mass, 0);
	assert_int_equal(base.where.line, 3);
	assert_int_equal(base.collisions.size(), 1);
	assert_true(base.collisions[0].shape.kind == SK::box);
	near3(base.collisions[0].shape.size, { 0.2, 0.2, 0.2 });

	const Link &upper = named(m.links, "upper_link");
	near(upper.mass, 1);
	near3(upper.pose.p, { 0, 0.15, 0 });
	near3(upper.inertial.p, { 0, 0.15, -0.5 });
	inertia(upper, { 1, 0.083, 1, 0, 0, 0 });
	assert_true(upper.collisions[0].shape.kind == SK::cylinder);
	near(upper.collisions[0].shape.radius, 0.05);
	near(upper.collisions[0].shape.length, 1.1);
	near3(upper.collisions[0].pose.p, { 0, 0.15, -0.5 });
	const Link &lower = named(m.links, "lower_link");
	near(lower.mass, 1);
	near3(lower.pose.p, { 0, 0.25, -1 });
	near3(lower.inertial.p, { 0, 0.25, -2 });
	inertia(lower, { 1, 0.33, 1, 0, 0, 0 });
	near(lower.collisions[0].shape.length, 2.1);

	assert_int_equal(m.joints.size(), 3);
	for (const char *name : { "shoulder", "elbow" }) {
		const Joint &j = named(m.joints, name);
		assert_true(j.kind == JK::continuous);
		near3(j.axis, { 0, 1, 0 });
		near(j.damping, 0.1);
		assert_false(j.lower || j.upper || j.effort_limit || j.velocity_limit);
	}
	const Joint &shoulder = named(m.joints, "shoulder"), &elbow = named(m.joints, "elbow");
	assert_string_equal(shoulder.parent.c_str(), "base_link");
	assert_string_equal(elbow.parent.c_str(), "upper_link");
	assert_string_equal(elbow.child.c_str(), "lower_link");
	near3(elbow.pose.p, { 0, 0.25, -1 });
	assert_int_equal(elbow.where.line, 73);
}

void test_cartpole(void **)
{
	std::string f = shared("cartpole.urdf");
	const Model m = load_ok(f).models.at(0);
	assert_string_equal(m.name.c_str(), "physics");
	assert_int_equal(m.links.size(), 3);
	// Bullet's mass-0 root: a fixed base, welded to the world.
	assert_string_equal(m.links[0].name.c_str(), "slideBar");
	near(m.links[0].mass, 0);
	assert_int_equal(m.links[0].collisions.size(), 0); // a visual only
	const Joint &weld = named(m.joints, "world_to_slideBar");
	assert_true(weld.kind == JK::fixed);
	assert_string_equal(weld.parent.c_str(), "world");
	near(named(m.links, "cart").mass, 1);
	inertia(named(m.links, "cart"), { 1, 1, 1, 0, 0, 0 });
	near3(named(m.links, "cart").collisions.at(0).shape.size, { 0.5, 0.5, 0.2 });
	const Link &pole = named(m.links, "pole");
	near(pole.mass, 10);
	near3(pole.inertial.p, { 0, 0, 0.5 });
	near3(pole.collisions.at(0).pose.p, { 0, 0, 0.5 });

	const Joint &slider = named(m.joints, "slider_to_cart");
	assert_true(slider.kind == JK::prismatic);
	near3(slider.axis, { 1, 0, 0 });
	near(*slider.lower, -15);
	near(*slider.upper, 15);
	near(*slider.effort_limit, 1000);
	near(*slider.velocity_limit, 5);
	const Joint &hinge = named(m.joints, "cart_to_pole");
	assert_true(hinge.kind == JK::continuous);
	near3(hinge.axis, { 0, 1, 0 });
	assert_string_equal(hinge.parent.c_str(), "cart");
	assert_false(hinge.lower.has_value());
}

void test_vehicle(void **)
{
	std::string f = shared("vehicle_model.sdf");
	const Model m = load_ok(f).models.at(0);
	assert_string_equal(m.name.c_str(), "vehicle");
	assert_int_equal(m.links.size(), 4);
	assert_int_equal(m.joints.size(), 3);
	const Link &chassis = named(m.links, "chassis");
	assert_int_equal(chassis.where.line, 4);
	near3(chassis.pose.p, { -0.151427, 0, 0.175 });
	near(chassis.mass, 1.14395);
	inertia(chassis, { 0.126164, 0.416519, 0.481014, 0, 0, 0 });
	near3(chassis.collisions.at(0).shape.size, { 2.01142, 1, 0.568726 });
	for (const char *w : { "left_wheel", "right_wheel" }) {
		const Link &l = named(m.links, w);
		near(l.mass, 2);
		same_rotation(l.pose.q, rpy(-1.5707, 0, 0));
		assert_true(l.collisions.at(0).shape.kind == SK::sphere);
		near(l.collisions.at(0).shape.radius, 0.3);
		// Revolute about the wheel's z, which its roll turns to the
		// model's y; "+-1.79769e+308" is no limit.
		const Joint &j = named(m.joints, std::string(w) + "_joint");
		assert_true(j.kind == JK::revolute);
		near3(j.axis, { 0, std::sin(1.5707), std::cos(1.5707) }, 1e-9);
		assert_false(j.lower || j.upper || j.effort_limit || j.velocity_limit);
		near3(j.pose.p, l.pose.p);
	}
	const Joint &caster = named(m.joints, "caster_wheel");
	assert_true(caster.kind == JK::ball);
	assert_string_equal(caster.child.c_str(), "caster");
	near(named(m.links, "caster").collisions.at(0).shape.radius, 0.2);
	assert_int_equal(m.sensors.size(), 0);
}

void test_double_pendulum_world(void **)
{
	std::string f = shared("double_pendulum_model.sdf");
	Description d = load_ok(f);
	assert_true(d.gravity.has_value());
	near3(*d.gravity, { 0, 0, -9.8 });
	near(*d.max_step_s, 0.001);
	assert_int_equal(d.models.size(), 2);
	const Model &ground = d.models[0];
	assert_string_equal(ground.name.c_str(), "ground_plane");
	assert_true(ground.is_static);
	const Collision &plane = ground.links.at(0).collisions.at(0);
	assert_true(plane.shape.kind == SK::plane);
	near3(plane.shape.normal, { 0, 0, 1 });

	const Model &m = d.models[1];
	assert_string_equal(m.name.c_str(), "double_pendulum_with_base0");
	assert_false(m.is_static);
	assert_int_equal(m.links.size(), 3);
	near(named(m.links, "base").mass, 100);
	assert_int_equal(named(m.links, "base").collisions.size(), 2);
	// An <inertial> with only a <pose>: SDF's defaults, mass 1 and a unit
	// inertia, at the pose in the link's (rolled) frame.
	const Link &upper = named(m.links, "upper_link");
	near(upper.mass, 1);
	inertia(upper, { 1, 1, 1, 0, 0, 0 });
	near3(upper.inertial.p, { 0, 0.5, 2.1 }, 1e-5);
	same_rotation(upper.pose.q, rpy(-1.5708, 0, 0));
	assert_false(upper.self_collide);
	for (const char *name : { "upper_joint", "lower_joint" }) {
		const Joint &j = named(m.joints, name);
		assert_true(j.kind == JK::revolute);
		near3(j.axis, { 1, 0, 0 }, 1e-9);
		assert_false(j.lower || j.upper || j.effort_limit);
	}
	near3(named(m.joints, "lower_joint").pose.p, { 0.25, 1.0, 2.1 });
}

// ---- the project's own files ----------------------------------------------------

void test_compound_pendulum_urdf(void **)
{
	const Model m = load_ok(own("compound_pendulum.urdf")).models.at(0);
	// bob is fixed to rod: lumped into it, with its collision and sensor.
	assert_int_equal(m.links.size(), 2);
	assert_false(has(m.links, "bob"));
	assert_false(has(m.joints, "bob_weld"));
	const Link &bracket = named(m.links, "bracket");
	near(bracket.mass, 0); // no <inertial>, welded to the declared world
	near3(bracket.pose.p, { 0, 0, 2 });
	near3(bracket.collisions.at(0).pose.p, { 0, 0, 2.05 });
	assert_string_equal(named(m.joints, "mount").parent.c_str(), "world");
	const Link &rod = named(m.links, "rod");
	near(rod.mass, 3);
	near3(rod.inertial.p, { 0, 0, 2 - (2 * 0.5 + 1 * 1.0) / 3 });
	same_rotation(rod.inertial.q, rpy(0, 0, pi / 2));
	assert_int_equal(rod.collisions.size(), 2);
	assert_true(rod.collisions[1].shape.kind == SK::sphere);
	near3(rod.collisions[1].pose.p, { 0, 0, 1 });
	const Joint &hinge = named(m.joints, "hinge");
	assert_true(hinge.kind == JK::revolute);
	near3(hinge.axis, { 1, 0, 0 });
	near(*hinge.lower, -3);
	near(*hinge.upper, 3);
	near(*hinge.effort_limit, 5);
	near(*hinge.velocity_limit, 10);
	near(hinge.damping, 0.05);
	near(hinge.friction, 0.01);
	assert_int_equal(hinge.where.line, 30);
	const Sensor &imu = named(m.sensors, "bob_imu");
	assert_true(imu.kind == Sensor::Kind::imu);
	assert_string_equal(imu.link.c_str(), "rod");
	near3(imu.pose.p, { 0, 0, 1 });
	near(imu.rate_hz, 500);
	assert_int_equal(imu.where.line, 52);
}

void test_wheeled_cart_urdf(void **)
{
	const Model m = load_ok(own("wheeled_cart.urdf")).models.at(0);
	assert_int_equal(m.links.size(), 2);
	for (const Joint &j : m.joints)
		assert_string_not_equal(j.parent.c_str(), "world"); // a free cart: its root has mass
	const Link &chassis = m.links[0];
	assert_string_equal(chassis.name.c_str(), "chassis");
	near(chassis.mass, 4);
	near3(chassis.inertial.p, { 0.1, 0, 0 });
	assert_int_equal(chassis.collisions.size(), 2);
	near3(chassis.collisions[1].pose.p, { 0.35, 0, 0 });
	assert_false(chassis.self_collide);
	const Joint &wheel = named(m.joints, "wheel_joint");
	assert_true(wheel.kind == JK::continuous);
	near3(wheel.axis, { 0, 1, 0 });
	near3(wheel.pose.p, { 0.2, 0.25, -0.05 });
	assert_false(wheel.lower || wheel.upper);
	near(*wheel.effort_limit, 2.5);
	near(*wheel.velocity_limit, 30);
	near(wheel.damping, 0.001);
	const Sensor &range = named(m.sensors, "range_front");
	assert_true(range.kind == Sensor::Kind::ray);
	assert_string_equal(range.link.c_str(), "chassis");
	near(range.range_min, 0.02);
	near(range.range_max, 4.5);
	near(range.rate_hz, 40);
	near3(range.pose.p, { 0.3, 0, 0.05 });
}

void test_two_link_arm_sdf(void **)
{
	Description d = load_ok(own("two_link_arm.sdf"));
	assert_false(d.gravity || d.max_step_s);
	const Model &m = d.models.at(0);
	near3(m.pose.p, { 1, 2, 0 });
	assert_int_equal(m.where.line, 9);
	assert_true(named(m.links, "base").self_collide);
	assert_true(named(m.links, "upper").self_collide);
	assert_false(named(m.links, "forearm").self_collide);
	assert_false(named(m.links, "upper").gravity);
	assert_true(named(m.links, "forearm").gravity);
	near(named(m.links, "upper").collisions.at(0).mu, 0.7);
	assert_true(named(m.links, "upper").collisions.at(0).shape.kind == SK::capsule);
	const Link &forearm = named(m.links, "forearm");
	same_rotation(forearm.pose.q, rpy(pi / 2, 0, 0));
	// The inertial frame, yawed 0.5 in the link's, in the model's.
	same_rotation(forearm.inertial.q, mul(rpy(pi / 2, 0, 0), rpy(0, 0, 0.5)));
	near3(forearm.inertial.p, { 0, 0, 0.8 });
	near3(forearm.collisions.at(0).pose.p, { 0, 0, 0.8 });

	assert_true(named(m.joints, "anchor").kind == JK::fixed);
	const Joint &shoulder = named(m.joints, "shoulder");
	near(*shoulder.lower, -1.5);
	near(*shoulder.upper, 1.5);
	near(*shoulder.effort_limit, 20);
	near(*shoulder.velocity_limit, 3);
	near(shoulder.damping, 0.2);
	near(shoulder.friction, 0.05);
	const Joint &elbow = named(m.joints, "elbow");
	near3(elbow.pose.p, { 0, 0, 0.6 });
	near3(elbow.axis, { 0, 1, 0 }, 1e-12); // -z of the rolled forearm
	assert_false(elbow.effort_limit.has_value()); // <effort>0</effort>
	assert_false(elbow.velocity_limit.has_value());

	assert_int_equal(m.sensors.size(), 4);
	const Sensor &imu = named(m.sensors, "forearm_imu");
	assert_true(imu.kind == Sensor::Kind::imu);
	near3(imu.pose.p, { 0, 0, 1 });
	near(imu.rate_hz, 1000);
	const Sensor &contact = named(m.sensors, "forearm_contact");
	assert_true(contact.kind == Sensor::Kind::contact);
	assert_string_equal(contact.link.c_str(), "forearm");
	const Sensor &ray = named(m.sensors, "range");
	assert_true(ray.kind == Sensor::Kind::ray);
	near(ray.range_min, 0.05);
	near(ray.range_max, 8);
	const Sensor &ft = named(m.sensors, "elbow_ft");
	assert_true(ft.kind == Sensor::Kind::force_torque);
	assert_string_equal(ft.joint.c_str(), "elbow");
	assert_string_equal(ft.link.c_str(), "forearm");
	near3(ft.pose.p, { 0, 0, 0.6 });
	near(ft.rate_hz, 250);
	assert_int_equal(ft.where.line, 86);
}

void test_joints_and_shapes_sdf(void **)
{
	const Model m = load_ok(own("joints_and_shapes.sdf")).models.at(0);
	assert_true(named(m.joints, "slide").kind == JK::prismatic);
	near(*named(m.joints, "slide").lower, -0.5);
	near(*named(m.joints, "slide").upper, 0.25);
	assert_true(named(m.joints, "spin").kind == JK::continuous);
	assert_true(named(m.joints, "ball").kind == JK::ball);
	const Joint &cross = named(m.joints, "cross");
	assert_true(cross.kind == JK::universal);
	near3(cross.axis, { 1, 0, 0 });
	near3(cross.axis2, { 0, 1, 0 });
	near3(cross.pose.p, { 0, 0, 4 });
	const SK kinds[] = { SK::box, SK::sphere, SK::cylinder, SK::capsule, SK::plane };
	for (size_t i = 0; i < m.links.size(); i++)
		assert_true(m.links[i].collisions.at(0).shape.kind == kinds[i]);
	near3(m.links[0].collisions[0].shape.size, { 1, 0.5, 0.25 });
	near(m.links[3].collisions[0].shape.radius, 0.05);
	near(m.links[3].collisions[0].shape.length, 0.3);
	near3(m.links[4].collisions[0].shape.normal, { 0, 0, 1 }); // written 0 0 2
}

void test_world_sdf(void **)
{
	Description d = load_ok(own("world.sdf"));
	near3(*d.gravity, { 0, 0, -3.71 });
	near(*d.max_step_s, 0.002);
	assert_int_equal(d.models.size(), 2);
	assert_true(d.models[0].is_static);
	near(d.models[0].links.at(0).collisions.at(0).mu, 0.4);
	near3(d.models[1].pose.p, { 1, 0, 0.5 });
	near(d.models[1].links.at(0).mass, 3);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_acrobot),
		cmocka_unit_test(test_cartpole),
		cmocka_unit_test(test_vehicle),
		cmocka_unit_test(test_double_pendulum_world),
		cmocka_unit_test(test_compound_pendulum_urdf),
		cmocka_unit_test(test_wheeled_cart_urdf),
		cmocka_unit_test(test_two_link_arm_sdf),
		cmocka_unit_test(test_joints_and_shapes_sdf),
		cmocka_unit_test(test_world_sdf),
	};
	int failed = cmocka_run_group_tests_name("robot files", tests, nullptr, nullptr);
	return failed + run_bad_robot_tests();
}
