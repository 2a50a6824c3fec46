// Unit tests for the collision mesh readers (simhost/robot/mesh_load.h):
// the files of tests/robots/meshes, and hostile ones written here; robot
// files with meshes in test_mesh_robots.cc.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

#include <filesystem>
#include <fstream>
#include <cstring>
#include <random>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "mesh_checks.h"
#include "mesh_load.h"

int run_mesh_robot_tests();

namespace {

using namespace mesh_checks;

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
	};
	int failed = cmocka_run_group_tests_name("mesh files", tests, setup, teardown);
	return failed + run_mesh_robot_tests();
}
