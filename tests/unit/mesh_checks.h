// What the mesh tests (test_mesh_load.cc, test_mesh_robots.cc) share:
// the project's robot files, a folder tree of the test's own (made by
// setup, removed by teardown) and a mesh's bounds, enclosed volume and
// box shape. Include after <cmocka.h>, and <fstream> before it (cmocka
// defines fail(), a name <fstream> uses).
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "robot_load_checks.h"

#ifndef TCS_TEST_ROBOTS_DIR
#error "TCS_TEST_ROBOTS_DIR must name the source tree's tests/robots folder"
#endif

namespace mesh_checks {

using namespace robot_checks;
namespace fs = std::filesystem;

inline std::string own(const std::string &name)
{
	return std::string(TCS_TEST_ROBOTS_DIR) + "/" + name;
}

// The test's folder tree (made by setup, removed by teardown).
inline std::string g_tmp;

inline std::string tmp(const std::string &name)
{
	return g_tmp + "/" + name;
}

inline void write(const std::string &path, const std::string &bytes)
{
	fs::create_directories(fs::path(path).parent_path());
	std::ofstream(path, std::ios::binary) << bytes;
}

inline std::string read(const std::string &path)
{
	std::ifstream f(path, std::ios::binary);
	return std::string(std::istreambuf_iterator<char>(f), {});
}

inline int setup(void **)
{
	char t[] = "/tmp/tcs-mesh-XXXXXX";
	if (!mkdtemp(t))
		return -1;
	g_tmp = t;
	return 0;
}

inline int teardown(void **)
{
	std::error_code ec;
	fs::remove_all(g_tmp, ec);
	return 0;
}

struct Bounds {
	Vec3 lo{ INFINITY, INFINITY, INFINITY }, hi{ -INFINITY, -INFINITY, -INFINITY };
};

inline Bounds bounds(const std::vector<Vec3> &v)
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
inline double signed_volume(const std::vector<Vec3> &v, const std::vector<unsigned> &ix)
{
	double s = 0;
	for (size_t t = 0; t + 2 < ix.size(); t += 3) {
		const Vec3 &a = v.at(ix[t]), &b = v.at(ix[t + 1]), &c = v.at(ix[t + 2]);
		s += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
		     a[2] * (b[0] * c[1] - b[1] * c[0]);
	}
	return s / 6;
}

inline void expect_box(const std::vector<Vec3> &v, const std::vector<unsigned> &ix, Vec3 lo, Vec3 hi)
{
	assert_int_equal(v.size(), 8);
	assert_int_equal(ix.size(), 36);
	Bounds b = bounds(v);
	near3(b.lo, lo, 1e-7);
	near3(b.hi, hi, 1e-7);
	near(signed_volume(v, ix), (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]), 1e-6);
}

} // namespace mesh_checks
