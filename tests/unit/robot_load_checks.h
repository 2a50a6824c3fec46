// cmocka checks for robot descriptions (simhost/robot/description.h):
// finding a link, joint or sensor by name, comparing numbers, vectors and
// rotations, and the loads' expected results. Include after <cmocka.h>.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include "description.h"
#include "sdf_load.h"

namespace robot_checks {

using namespace tcs::sim::robot;

inline Description load_ok(const std::string &path)
{
	auto r = load_robot_file(path);
	if (!r.ok()) {
		print_error("load_robot_file(%s): %s\n", path.c_str(), r.error().message.c_str());
		fail();
	}
	return std::move(*r);
}

// The error of a file that must fail: exactly "PATH:LINE: ..." (line 0:
// "PATH: ...") with each of the words in it.
inline void load_fails(const std::string &path, int line, std::initializer_list<const char *> words)
{
	auto r = load_robot_file(path);
	if (r.ok()) {
		print_error("load_robot_file(%s) succeeded, should fail at line %d\n", path.c_str(), line);
		fail();
	}
	const std::string &m = r.error().message;
	std::string prefix = line > 0 ? path + ":" + std::to_string(line) + ": " : path + ": ";
	bool ok = m.compare(0, prefix.size(), prefix) == 0 && m.find('\n') == std::string::npos;
	for (const char *w : words)
		ok = ok && m.find(w) != std::string::npos;
	if (!ok) {
		print_error("%s: got \"%s\", want \"%s...\" with", path.c_str(), m.c_str(), prefix.c_str());
		for (const char *w : words)
			print_error(" \"%s\"", w);
		print_error("\n");
		fail();
	}
}

template <class T> const T &named(const std::vector<T> &v, const std::string &name)
{
	for (const T &x : v)
		if (x.name == name)
			return x;
	print_error("no %s in the description\n", name.c_str());
	fail();
	return v.front();
}

template <class T> bool has(const std::vector<T> &v, const std::string &name)
{
	for (const T &x : v)
		if (x.name == name)
			return true;
	return false;
}

inline void near(double got, double want, double eps = 1e-9)
{
	if (!(std::fabs(got - want) <= eps)) {
		print_error("got %.12g, want %.12g (+-%g)\n", got, want, eps);
		fail();
	}
}

inline void near3(const Vec3 &got, const Vec3 &want, double eps = 1e-9)
{
	for (int i = 0; i < 3; i++)
		near(got[i], want[i], eps);
}

// Rotations compared as rotations: q and -q are one.
inline void same_rotation(const Quat &got, const Quat &want, double eps = 1e-6)
{
	double dot = 0;
	for (int i = 0; i < 4; i++)
		dot += got[i] * want[i];
	near(std::fabs(dot), 1.0, eps);
}

inline Quat rpy(double r, double p, double y)
{
	double cr = std::cos(r / 2), sr = std::sin(r / 2), cp = std::cos(p / 2), sp = std::sin(p / 2);
	double cy = std::cos(y / 2), sy = std::sin(y / 2);
	return { cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
		 cr * cp * sy - sr * sp * cy };
}

inline Quat mul(const Quat &a, const Quat &b)
{
	return { a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
		 a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
		 a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
		 a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0] };
}

inline void inertia(const Link &l, std::array<double, 6> want, double eps = 1e-9)
{
	for (int i = 0; i < 6; i++)
		near(l.inertia[i], want[i], eps);
}

} // namespace robot_checks
