// What the robot model's tests share: robot descriptions built by hand
// (links with a box's mass and inertia, joints, sensors), quaternions, and
// a model made from one with its signals looked up by name. Include after
// <cmocka.h>.
#pragma once

#include <time.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "description.h"
#include "ode_robot.h"
#include "result_checks.h"

namespace robot_checks {

namespace r = tcs::sim::robot;

inline constexpr double g = 9.81;
inline constexpr double dt = 1e-3;

inline double now_s()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

inline r::Quat axis_angle(r::Vec3 axis, double angle)
{
	double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
	double s = std::sin(angle / 2) / n;
	return { std::cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s };
}

inline r::Pose pose(double x, double y, double z, r::Quat q = { 1, 0, 0, 0 })
{
	return { { x, y, z }, q };
}

// A uniform box of `size` and `mass`, its link frame at `at`, its centre
// of mass at `com` (model frame) with the box's axes turned by `axes`.
inline r::Link box_link(const char *name, double mass, r::Vec3 size, r::Pose at, r::Vec3 com,
			r::Quat axes = { 1, 0, 0, 0 })
{
	r::Link l;
	l.name = name;
	l.pose = at;
	l.mass = mass;
	l.inertial = { com, axes };
	double x2 = size[0] * size[0], y2 = size[1] * size[1], z2 = size[2] * size[2];
	l.inertia = { mass * (y2 + z2) / 12, mass * (x2 + z2) / 12, mass * (x2 + y2) / 12, 0, 0, 0 };
	return l;
}

inline r::Collision box_collision(const char *name, r::Vec3 size, r::Pose at, double mu = 1)
{
	r::Collision c;
	c.name = name;
	c.pose = at;
	c.shape.kind = r::Shape::Kind::box;
	c.shape.size = size;
	c.mu = mu;
	return c;
}

inline r::Joint joint(const char *name, r::Joint::Kind kind, const char *parent, const char *child, r::Pose at,
		      r::Vec3 axis = { 0, 1, 0 })
{
	r::Joint j;
	j.name = name;
	j.kind = kind;
	j.parent = parent;
	j.child = child;
	j.pose = at;
	j.axis = axis;
	return j;
}

inline r::Sensor sensor(const char *name, r::Sensor::Kind kind, const char *link, r::Pose at)
{
	r::Sensor s;
	s.name = name;
	s.kind = kind;
	s.link = link;
	s.pose = at;
	return s;
}

// A model made from a description, its signals looked up by name (a
// missing one fails the test).
class Bot {
public:
	Bot(const r::Model &desc, const tcs::sim::RobotOptions &opts = {}, const char *name = "r")
		: model_(MUST(tcs::sim::make_robot_model(name, desc, opts))), prefix_(std::string(name) + ".")
	{
		model_->describe(signals_);
	}

	const std::vector<tcs::sim::SignalDesc> &signals() const { return signals_; }
	uint32_t index(const std::string &name) const
	{
		for (size_t i = 0; i < signals_.size(); i++)
			if (signals_[i].name == prefix_ + name)
				return (uint32_t)i;
		print_error("no signal %s%s\n", prefix_.c_str(), name.c_str());
		fail();
		return 0;
	}
	std::vector<double> values(const std::string &name) const
	{
		uint32_t i = index(name);
		std::vector<double> v(signals_[i].width);
		model_->read(i, v.data());
		return v;
	}
	double get(const std::string &name) const { return values(name)[0]; }
	void set(const std::string &name, double v)
	{
		uint32_t i = index(name);
		assert_true(signals_[i].flags & TCS_SIM_SIGNAL_WRITABLE);
		model_->write(i, &v);
	}
	void step(int n = 1)
	{
		for (int i = 0; i < n; i++)
			CHECK_OK(model_->step(dt));
	}

private:
	std::unique_ptr<tcs::sim::Model> model_;
	std::string prefix_;
	std::vector<tcs::sim::SignalDesc> signals_;
};

// make_robot_model's message for a description that must be refused.
inline std::string refusal(const r::Model &desc, const tcs::sim::RobotOptions &opts = {})
{
	auto m = tcs::sim::make_robot_model("r", desc, opts);
	if (m.ok()) {
		print_error("make_robot_model succeeded, expected an error\n");
		fail();
	}
	return m.error().message;
}

inline void expect_contains(const std::string &text, const char *part)
{
	if (text.find(part) == std::string::npos) {
		print_error("'%s' does not contain '%s'\n", text.c_str(), part);
		fail();
	}
}

inline void expect_near(double got, double want, double tol, const char *what)
{
	if (!(std::fabs(got - want) <= tol)) {
		print_error("%s: got %.9g, want %.9g (tolerance %.3g)\n", what, got, want, tol);
		fail();
	}
}

} // namespace robot_checks
