// Collision meshes in robot files: URI resolution (mesh_uri.h) in a
// folder tree made here, URDF and SDF files with relative, package:// and
// model:// meshes, their errors, and a mesh cube from a URDF resting on a
// plane through the ODE model.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "mesh_checks.h"
#include "mesh_uri.h"
#include "robot_models.h"

int run_mesh_robot_tests();

namespace {

using namespace mesh_checks;

// ---- URIs -----------------------------------------------------------------------

void expect_resolves(const std::string &uri, const std::string &robot, const std::string &want)
{
	auto p = resolve_mesh_uri(uri, robot);
	if (!p.ok()) {
		print_error("%s: %s\n", uri.c_str(), p.error().message.c_str());
		fail();
	}
	if (fs::path(*p) != fs::path(want).lexically_normal()) {
		print_error("%s: got %s, want %s\n", uri.c_str(), p->c_str(), want.c_str());
		fail();
	}
}

void expect_unresolved(const std::string &uri, const std::string &robot, std::initializer_list<const char *> words)
{
	auto p = resolve_mesh_uri(uri, robot);
	if (p.ok()) {
		print_error("%s resolved to %s, should not\n", uri.c_str(), p->c_str());
		fail();
	}
	for (const char *w : words)
		expect_contains(p.error().message, w);
}

void clear_env()
{
	for (const char *v : { "ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH", "GZ_SIM_RESOURCE_PATH",
			       "IGN_GAZEBO_RESOURCE_PATH", "SDF_PATH", "GAZEBO_MODEL_PATH" })
		unsetenv(v);
}

void test_uris(void **)
{
	clear_env();
	const std::string robot = tmp("ws/src/pkg/urdf/r.urdf");
	write(robot, "");
	write(tmp("ws/src/pkg/meshes/m.stl"), "x");
	write(tmp("elsewhere/other/meshes/o.stl"), "x");
	write(tmp("ament/share/amentpkg/meshes/a.stl"), "x");
	write(tmp("models/mod/meshes/x.obj"), "x");

	expect_resolves("../meshes/m.stl", robot, tmp("ws/src/pkg/meshes/m.stl"));
	expect_resolves("file://../meshes/m.stl", robot, tmp("ws/src/pkg/meshes/m.stl"));
	expect_resolves("file://" + tmp("elsewhere/other/meshes/o.stl"), robot, tmp("elsewhere/other/meshes/o.stl"));
	expect_resolves(tmp("elsewhere/other/meshes/o.stl"), robot, tmp("elsewhere/other/meshes/o.stl"));
	expect_unresolved("meshes/m.stl", robot, { "mesh 'meshes/m.stl' not found (looked in: ", "urdf/meshes/m.stl)" });

	// package://: the file's own package, found above it.
	expect_resolves("package://pkg/meshes/m.stl", robot, tmp("ws/src/pkg/meshes/m.stl"));
	expect_unresolved("package://other/meshes/o.stl", robot,
			  { "not found", "$ROS_PACKAGE_PATH (unset)", "no folder 'other' above" });
	// Through ROS_PACKAGE_PATH: a folder holding the package, or the
	// package's own folder.
	setenv("ROS_PACKAGE_PATH", ("/nonexistent:" + tmp("elsewhere")).c_str(), 1);
	expect_resolves("package://other/meshes/o.stl", robot, tmp("elsewhere/other/meshes/o.stl"));
	setenv("ROS_PACKAGE_PATH", tmp("elsewhere/other/").c_str(), 1);
	expect_resolves("package://other/meshes/o.stl", robot, tmp("elsewhere/other/meshes/o.stl"));
	expect_unresolved("package://other/meshes/gone.stl", robot,
			  { "elsewhere/other/meshes/gone.stl", "no folder 'other' above" });
	unsetenv("ROS_PACKAGE_PATH");
	setenv("AMENT_PREFIX_PATH", tmp("ament").c_str(), 1);
	expect_resolves("package://amentpkg/meshes/a.stl", robot, tmp("ament/share/amentpkg/meshes/a.stl"));
	unsetenv("AMENT_PREFIX_PATH");

	// model://: each of Gazebo's variables, and above the file.
	for (const char *v : { "GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "SDF_PATH", "GAZEBO_MODEL_PATH" }) {
		setenv(v, tmp("models").c_str(), 1);
		expect_resolves("model://mod/meshes/x.obj", robot, tmp("models/mod/meshes/x.obj"));
		unsetenv(v);
	}
	expect_unresolved("model://mod/meshes/x.obj", robot, { "not found", "$SDF_PATH (unset)", "no folder 'mod'" });
	expect_resolves("model://pkg/meshes/m.stl", robot, tmp("ws/src/pkg/meshes/m.stl"));

	expect_unresolved("https://example.com/m.stl", robot, { "relative path, file://, package:// and model://" });
	expect_unresolved("package://pkg", robot, { "names a package and a file in it" });
	expect_unresolved("", robot, { "relative path" });
	// A folder is not a mesh.
	expect_unresolved("package://pkg/meshes", robot, { "not found" });
}

// ---- robot files ----------------------------------------------------------------

const Shape &mesh_of(const Link &l, size_t i)
{
	const Shape &s = l.collisions.at(i).shape;
	assert_true(s.kind == Shape::Kind::mesh);
	return s;
}

void test_urdf(void **)
{
	clear_env();
	const Model m = load_ok(own("mesh_cube.urdf")).models.at(0);
	const Shape &cube = mesh_of(named(m.links, "cube"), 0);
	expect_box(cube.vertices, cube.indices, { -0.1, -0.1, -0.1 }, { 0.1, 0.1, 0.1 });
	assert_string_equal(cube.mesh_uri.c_str(), "package://robots/meshes/cube.stl");

	const Model arm = load_ok(own("mesh_arm.urdf")).models.at(0);
	assert_int_equal(arm.links.size(), 2); // the lid lumped into the base
	const Link &base = named(arm.links, "base");
	assert_int_equal(base.collisions.size(), 2);
	const Shape &body = mesh_of(base, 0);
	expect_box(body.vertices, body.indices, { -0.5, -0.5, -0.5 }, { 0.5, 0.5, 0.5 });
	assert_string_equal(body.mesh_uri.c_str(), "meshes/cube_ascii.stl");
	const Shape &lid = mesh_of(base, 1);
	expect_box(lid.vertices, lid.indices, { -0.5, -0.25, 0 }, { 0.5, 0.25, 0.25 });
	assert_string_equal(lid.mesh_uri.c_str(), "./meshes/box.obj");
	near3(base.collisions[1].pose.p, { 0, 0, 0.5 });
	const Link &a = named(arm.links, "arm");
	const Shape &bar = mesh_of(a, 0);
	// Mirrored in z: still wound outward (a positive volume).
	expect_box(bar.vertices, bar.indices, { -0.1, -1, -0.5 }, { 0.1, 1, 0 });
	near3(a.collisions[0].pose.p, { 0, 0, 1.1 });

	// package:// through ROS_PACKAGE_PATH, from a URDF outside the package.
	write(tmp("share/meshpkg/meshes/cube.stl"), read(own("meshes/cube.stl")));
	const std::string urdf = tmp("robot/r.urdf");
	write(urdf, "<?xml version=\"1.0\"?>\n<robot name=\"r\">\n<link name=\"a\">\n"
		    "<inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>\n"
		    "<collision><geometry>\n<mesh filename=\"package://meshpkg/meshes/cube.stl\" scale=\"2 2 2\"/>\n"
		    "</geometry></collision>\n</link>\n</robot>\n");
	load_fails(urdf, 6, { "mesh 'package://meshpkg/meshes/cube.stl' not found (looked in: ", "$ROS_PACKAGE_PATH (unset)" });
	setenv("ROS_PACKAGE_PATH", tmp("share").c_str(), 1);
	const Model r = load_ok(urdf).models.at(0);
	const Shape &s = mesh_of(r.links.at(0), 0);
	expect_box(s.vertices, s.indices, { -1, -1, -1 }, { 1, 1, 1 });
	unsetenv("ROS_PACKAGE_PATH");
}

void test_sdf(void **)
{
	clear_env();
	const Model m = load_ok(own("mesh_shapes.sdf")).models.at(0);
	const Shape &stl = mesh_of(named(m.links, "stl"), 0);
	expect_box(stl.vertices, stl.indices, { -0.05, -0.1, -0.15 }, { 0.05, 0.1, 0.15 });
	assert_string_equal(stl.mesh_uri.c_str(), "meshes/cube_ascii.stl");
	const Link &obj = named(m.links, "obj");
	const Shape &box = mesh_of(obj, 0);
	expect_box(box.vertices, box.indices, { -1, -0.5, 0 }, { 1, 0.5, 0.5 });
	near3(obj.collisions[0].pose.p, { 0, 0, 1.5 });
	assert_string_equal(box.mesh_uri.c_str(), "model://robots/meshes/box.obj");
	const Shape &bin = mesh_of(named(m.links, "binary"), 0);
	expect_box(bin.vertices, bin.indices, { -0.5, -0.5, -0.5 }, { 0.5, 0.5, 0.5 });

	// model:// through GZ_SIM_RESOURCE_PATH, from an SDF elsewhere.
	write(tmp("gz/crate/meshes/box.obj"), read(own("meshes/box.obj")));
	const std::string sdf = tmp("world/crate.sdf");
	write(sdf, "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\">\n<model name=\"crate\">\n<link name=\"a\">\n"
		   "<inertial><mass>1</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz></inertia></inertial>\n"
		   "<collision name=\"hull\">\n"
		   "<geometry><mesh><uri>model://crate/meshes/box.obj</uri></mesh></geometry>\n"
		   "</collision>\n</link>\n</model>\n</sdf>\n");
	load_fails(sdf, 6, { "mesh 'model://crate/meshes/box.obj' not found", "$GZ_SIM_RESOURCE_PATH (unset)" });
	setenv("GZ_SIM_RESOURCE_PATH", tmp("gz").c_str(), 1);
	assert_int_equal(mesh_of(load_ok(sdf).models.at(0).links.at(0), 0).indices.size(), 36);
	unsetenv("GZ_SIM_RESOURCE_PATH");
}

void test_bad_robot_files(void **)
{
	clear_env();
	const std::string bad = own("bad/");
	load_fails(bad + "mesh.urdf", 7, { "mesh 'package://robot/meshes/a.stl' not found", "no folder 'robot'" });
	load_fails(bad + "mesh.sdf", 6, { "mesh 'meshes/a.stl' not found", "bad/meshes/a.stl" });
	load_fails(bad + "submesh.sdf", 6, { "collision 'hull'", "submesh 'lid'", "mesh file of its own" });

	// A mesh the loader refuses: the robot file's line, then the mesh's words.
	write(tmp("parts/wheel.dae"), "<COLLADA/>");
	write(tmp("parts/cut.stl"), read(own("meshes/cube.stl")).substr(0, 200));
	const char *head = "<?xml version=\"1.0\"?>\n<robot name=\"r\">\n<link name=\"a\">\n"
			   "<inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>\n"
			   "<collision><geometry>\n";
	const char *tail = "</geometry></collision>\n</link>\n</robot>\n";
	write(tmp("parts/dae.urdf"), std::string(head) + "<mesh filename=\"wheel.dae\"/>\n" + tail);
	load_fails(tmp("parts/dae.urdf"), 6, { "mesh 'wheel.dae'", "Collada (.dae)", "convert it to STL" });
	write(tmp("parts/cut.urdf"), std::string(head) + "<mesh filename=\"cut.stl\"/>\n" + tail);
	load_fails(tmp("parts/cut.urdf"), 6, { "mesh 'cut.stl'", "cut.stl: a binary STL claiming 12 triangles" });
	write(tmp("parts/nameless.urdf"), std::string(head) + "<mesh/>\n" + tail);
	load_fails(tmp("parts/nameless.urdf"), 6, { "<mesh> without a filename" });
	write(tmp("parts/zero_scale.urdf"), std::string(head) + "<mesh filename=\"wheel.dae\" scale=\"1 0 1\"/>\n" + tail);
	load_fails(tmp("parts/zero_scale.urdf"), 6, { "non-zero" });
}

// ---- physics --------------------------------------------------------------------

void test_mesh_cube_rests(void **)
{
	// The URDF's mesh cube (edge 0.2 m) dropped a millimetre onto a
	// plane: it rests at its half height, bearing its weight.
	clear_env();
	Link cube = load_ok(own("mesh_cube.urdf")).models.at(0).links.at(0);
	const double z = 0.101;
	cube.pose = pose(1, 0, z);
	cube.inertial.p = { 1, 0, z };
	cube.collisions.at(0).pose = pose(1, 0, z);
	cube.self_collide = true;
	r::Model m = floor_and_mast();
	m.links.push_back(cube);
	m.sensors.push_back(sensor("touch", r::Sensor::Kind::contact, "cube", pose(1, 0, z)));
	tcs::sim::RobotOptions o;
	o.fixed = true;
	Bot bot(m, o);
	bot.step(1000);
	std::vector<double> p = bot.values("cube.pose");
	print_message("mesh cube at rest: centre at %.6f m, %g contacts, force %.4f N\n", p[2], bot.get("touch.count"),
		      bot.values("touch.force")[2]);
	expect_near(p[2], 0.1, 1e-5, "resting height");
	expect_near(p[0], 1, 1e-6, "x");
	expect_near(bot.values("touch.force")[2], 2 * g, 2e-3 * g, "weight borne");
	expect_near(bot.values("cube.twist")[2], 0, 1e-6, "at rest");
}

} // namespace

int run_mesh_robot_tests()
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_uris),
		cmocka_unit_test(test_urdf),
		cmocka_unit_test(test_sdf),
		cmocka_unit_test(test_bad_robot_files),
		cmocka_unit_test(test_mesh_cube_rests),
	};
	return cmocka_run_group_tests_name("meshes in robot files", tests, setup, teardown);
}
