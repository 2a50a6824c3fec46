// Unit tests for collision meshes: the STL and OBJ readers
// (simhost/robot/mesh_load.h) on the files of tests/robots/meshes and on
// hostile ones written here, URI resolution (mesh_uri.h) in a folder tree
// made here, robot files with meshes (URDF and SDF, relative, package://
// and model:// URIs), and a mesh cube from a URDF resting on a plane.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "mesh_load.h"
#include "mesh_uri.h"
#include "robot_load_checks.h"
#include "robot_models.h"

#ifndef TCS_TEST_ROBOTS_DIR
#error "TCS_TEST_ROBOTS_DIR must name the source tree's tests/robots folder"
#endif

namespace {

using namespace robot_checks;
namespace fs = std::filesystem;

std::string own(const std::string &name)
{
	return std::string(TCS_TEST_ROBOTS_DIR) + "/" + name;
}

// The test's folder tree (made by setup, removed by teardown).
std::string g_tmp;

std::string tmp(const std::string &name)
{
	return g_tmp + "/" + name;
}

void write(const std::string &path, const std::string &bytes)
{
	fs::create_directories(fs::path(path).parent_path());
	std::ofstream(path, std::ios::binary) << bytes;
}

std::string read(const std::string &path)
{
	std::ifstream f(path, std::ios::binary);
	return std::string(std::istreambuf_iterator<char>(f), {});
}

int setup(void **)
{
	char t[] = "/tmp/tcs-mesh-XXXXXX";
	if (!mkdtemp(t))
		return -1;
	g_tmp = t;
	return 0;
}

int teardown(void **)
{
	std::error_code ec;
	fs::remove_all(g_tmp, ec);
	return 0;
}

Mesh mesh_ok(const std::string &path, Vec3 scale = { 1, 1, 1 })
{
	auto m = load_mesh(path, scale);
	if (!m.ok()) {
		print_error("load_mesh(%s): %s\n", path.c_str(), m.error().message.c_str());
		fail();
	}
	return std::move(*m);
}

// The error of a mesh that must fail: "PATH: ..." or "PATH:LINE: ...",
// on one line, with each of the words.
void mesh_fails(const std::string &path, std::initializer_list<const char *> words, Vec3 scale = { 1, 1, 1 })
{
	auto m = load_mesh(path, scale);
	if (m.ok()) {
		print_error("load_mesh(%s) succeeded, should fail\n", path.c_str());
		fail();
	}
	const std::string &e = m.error().message;
	bool ok = e.rfind(path + ":", 0) == 0 && e.find('\n') == std::string::npos;
	for (const char *w : words)
		ok = ok && e.find(w) != std::string::npos;
	if (!ok) {
		print_error("%s: got \"%s\", want it with", path.c_str(), e.c_str());
		for (const char *w : words)
			print_error(" \"%s\"", w);
		print_error("\n");
		fail();
	}
}

struct Bounds {
	Vec3 lo{ INFINITY, INFINITY, INFINITY }, hi{ -INFINITY, -INFINITY, -INFINITY };
};

Bounds bounds(const std::vector<Vec3> &v)
{
	Bounds b;
	for (const Vec3 &x : v)
		for (int i = 0; i < 3; i++) {
			b.lo[i] = std::min(b.lo[i], x[i]);
			b.hi[i] = std::max(b.hi[i], x[i]);
		}
	return b;
}

// The volume the triangles enclose, positive when they are wound
// counter-clockwise seen from outside (what ODE takes as outward).
double signed_volume(const std::vector<Vec3> &v, const std::vector<unsigned> &ix)
{
	double s = 0;
	for (size_t t = 0; t + 2 < ix.size(); t += 3) {
		const Vec3 &a = v.at(ix[t]), &b = v.at(ix[t + 1]), &c = v.at(ix[t + 2]);
		s += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
		     a[2] * (b[0] * c[1] - b[1] * c[0]);
	}
	return s / 6;
}

void expect_box(const std::vector<Vec3> &v, const std::vector<unsigned> &ix, Vec3 lo, Vec3 hi)
{
	assert_int_equal(v.size(), 8);
	assert_int_equal(ix.size(), 36);
	Bounds b = bounds(v);
	near3(b.lo, lo, 1e-7);
	near3(b.hi, hi, 1e-7);
	near(signed_volume(v, ix), (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]), 1e-6);
}

// ---- the readers on good files --------------------------------------------------

void test_stl(void **)
{
	Mesh bin = mesh_ok(own("meshes/cube.stl"));
	expect_box(bin.vertices, bin.indices, { -0.5, -0.5, -0.5 }, { 0.5, 0.5, 0.5 });
	Mesh text = mesh_ok(own("meshes/cube_ascii.stl"));
	expect_box(text.vertices, text.indices, { -0.5, -0.5, -0.5 }, { 0.5, 0.5, 0.5 });
	// Same triangles in the same order: the same indexed mesh.
	assert_true(bin.indices == text.indices);
	for (size_t i = 0; i < bin.vertices.size(); i++)
		near3(bin.vertices[i], text.vertices[i], 0);
	Mesh small = mesh_ok(own("meshes/cube.stl"), { 0.2, 0.4, 2 });
	expect_box(small.vertices, small.indices, { -0.1, -0.2, -1 }, { 0.1, 0.2, 1 });
}

void test_obj(void **)
{
	// Six quads in every corner form, one face by negative indices, a
	// duplicate vertex (merged): 12 triangles on 8 vertices.
	Mesh m = mesh_ok(own("meshes/box.obj"));
	expect_box(m.vertices, m.indices, { -1, -0.5, 0 }, { 1, 0.5, 0.5 });
	// A mirroring scale keeps the outside out.
	Mesh mirrored = mesh_ok(own("meshes/box.obj"), { 1, 1, -2 });
	expect_box(mirrored.vertices, mirrored.indices, { -1, -0.5, -1 }, { 1, 0.5, 0 });
	// A pentagon fanned into three triangles; lines tcs does not need.
	write(tmp("pentagon.obj"), "# comment\nv 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 2 0\nv -0.5 1 0\n"
				   "vn 0 0 1\nvt 0 0\nl 1 2\ns 1\nf 1/1/1 2/1/1 3/1/1 4/1/1 5/1/1\n");
	Mesh p = mesh_ok(tmp("pentagon.obj"));
	assert_int_equal(p.vertices.size(), 5);
	assert_int_equal(p.indices.size(), 9);
	// Windows line ends, a leading '+', exponents.
	write(tmp("crlf.obj"), "v +0 0 0\r\nv 1e0 0 0\r\nv 0 1.0E+0 0\r\nf 1 2 3\r\n");
	assert_int_equal(mesh_ok(tmp("crlf.obj")).indices.size(), 3);
}

// ---- hostile files --------------------------------------------------------------

std::string binary_stl(uint32_t count, size_t triangles_written)
{
	std::string b(80, ' ');
	b.append(reinterpret_cast<const char *>(&count), 4);
	b.append(50 * triangles_written, '\0');
	return b;
}

void test_hostile_stl(void **)
{
	std::string cube = read(own("meshes/cube.stl"));
	write(tmp("truncated.stl"), cube.substr(0, 400));
	mesh_fails(tmp("truncated.stl"), { "claiming 12 triangles", "684 bytes", "400 bytes", "truncated" });
	write(tmp("huge.stl"), binary_stl(1000000000u, 1));
	mesh_fails(tmp("huge.stl"), { "claiming 1000000000 triangles" });
	write(tmp("max.stl"), binary_stl(0xffffffffu, 0));
	mesh_fails(tmp("max.stl"), { "claiming 4294967295 triangles" });
	// A NaN coordinate in the fifth triangle.
	std::string nan = cube;
	float f = NAN;
	std::memcpy(&nan[84 + 4 * 50 + 12 + 4], &f, 4);
	write(tmp("nan.stl"), nan);
	mesh_fails(tmp("nan.stl"), { "triangle 5", "not finite" });
	write(tmp("empty.stl"), binary_stl(0, 0));
	mesh_fails(tmp("empty.stl"), { "no triangles" });
	write(tmp("short.stl"), "abc");
	mesh_fails(tmp("short.stl"), { "not an STL" });
	write(tmp("zero_area.stl"), "solid z\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 0 0\n"
				    "vertex 1 0 0\nendloop\nendfacet\nendsolid z\n");
	mesh_fails(tmp("zero_area.stl"), { "no triangles" });

	std::string text = read(own("meshes/cube_ascii.stl"));
	write(tmp("cut.stl"), text.substr(0, 300));
	mesh_fails(tmp("cut.stl"), { "ends inside the facet of line" });
}

void test_hostile_text(void **)
{
	write(tmp("nan_ascii.stl"), "solid n\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\n");
	mesh_fails(tmp("nan_ascii.stl"), { ":5:", "'nan'", "not a finite number" });
	write(tmp("quad.stl"), "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"
			       "vertex 0 1 0\nendloop\nendfacet\nendsolid q\n");
	mesh_fails(tmp("quad.stl"), { ":7:", "more than 3 vertices" });
	write(tmp("junk.stl"), "solid j\n\x01\x02\xff garbage\n");
	mesh_fails(tmp("junk.stl"), { ":2:", "not an STL keyword" });

	write(tmp("past.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
	mesh_fails(tmp("past.obj"), { ":4:", "'9'", "past the 3 vertices" });
	write(tmp("zero.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
	mesh_fails(tmp("zero.obj"), { ":4:", "'0'" });
	write(tmp("negative.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
	mesh_fails(tmp("negative.obj"), { ":4:", "'-4'", "past" });
	write(tmp("forward.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n");
	mesh_fails(tmp("forward.obj"), { ":3:", "past the 2 vertices" });
	write(tmp("nan.obj"), "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
	mesh_fails(tmp("nan.obj"), { ":2:", "'nan'" });
	write(tmp("inf.obj"), "v 0 0 0\nv 1 1e999 0\nv 0 1 0\nf 1 2 3\n");
	mesh_fails(tmp("inf.obj"), { ":2:", "'1e999'" });
	write(tmp("short_v.obj"), "v 0 0\n");
	mesh_fails(tmp("short_v.obj"), { ":1:", "3 numbers" });
	write(tmp("line_face.obj"), "v 0 0 0\nv 1 0 0\nf 1 2\n");
	mesh_fails(tmp("line_face.obj"), { ":3:", "at least 3 corners" });
	write(tmp("word.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x/1\n");
	mesh_fails(tmp("word.obj"), { ":4:", "'x/1'", "not a vertex index" });
	write(tmp("huge_index.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n");
	mesh_fails(tmp("huge_index.obj"), { ":4:", "not a vertex index" });
	write(tmp("no_faces.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
	mesh_fails(tmp("no_faces.obj"), { "no triangles" });
	// A huge coordinate is finite; scaled, it is not.
	write(tmp("big.obj"), "v 0 0 0\nv 1e308 0 0\nv 0 1 0\nf 1 2 3\n");
	mesh_ok(tmp("big.obj"));
	mesh_fails(tmp("big.obj"), { "not finite once scaled" }, { 10, 1, 1 });
	mesh_fails(tmp("big.obj"), { "scale", "non-zero" }, { 1, 0, 1 });
	mesh_fails(tmp("big.obj"), { "scale", "finite" }, { 1, NAN, 1 });
}

void test_other_formats(void **)
{
	write(tmp("part.dae"), "<COLLADA/>");
	mesh_fails(tmp("part.dae"), { "tcs reads STL and OBJ meshes", "Collada (.dae)", "convert it to STL" });
	write(tmp("part.glb"), "glTF");
	mesh_fails(tmp("part.glb"), { "glTF" });
	write(tmp("part.xyz"), "");
	mesh_fails(tmp("part.xyz"), { ".xyz files" });
	// Upper-case extensions are the same formats.
	write(tmp("CUBE.STL"), read(own("meshes/cube.stl")));
	assert_int_equal(mesh_ok(tmp("CUBE.STL")).indices.size(), 36);
	mesh_fails(tmp("absent.stl"), { "No such file" });
}

// Random bytes and damaged copies of good files: an answer, never a crash.
void test_random_bytes(void **)
{
	std::mt19937 rng(19);
	std::string good[] = { read(own("meshes/cube.stl")), read(own("meshes/cube_ascii.stl")),
			       read(own("meshes/box.obj")) };
	const char *ext[] = { ".stl", ".stl", ".obj" };
	for (int i = 0; i < 600; i++) {
		int k = i % 3;
		std::string b = good[k];
		if (i % 2) {
			b.resize(rng() % 300);
			for (char &c : b)
				c = (char)(rng() & 0xff);
			if (k == 1)
				b = "solid x\n" + b;
		} else {
			for (int n = 0; n < 4; n++)
				b[rng() % b.size()] = (char)(rng() & 0xff);
			b.resize(rng() % (b.size() + 1));
		}
		std::string p = tmp("random" + std::to_string(i % 3) + ext[k]);
		write(p, b);
		auto m = load_mesh(p, { 1, 1, 1 });
		if (m.ok())
			for (unsigned ix : m->indices)
				assert_true(ix < m->vertices.size());
	}
}

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

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stl),
		cmocka_unit_test(test_obj),
		cmocka_unit_test(test_hostile_stl),
		cmocka_unit_test(test_hostile_text),
		cmocka_unit_test(test_other_formats),
		cmocka_unit_test(test_random_bytes),
		cmocka_unit_test(test_uris),
		cmocka_unit_test(test_urdf),
		cmocka_unit_test(test_sdf),
		cmocka_unit_test(test_bad_robot_files),
		cmocka_unit_test(test_mesh_cube_rests),
	};
	return cmocka_run_group_tests_name("meshes", tests, setup, teardown);
}
