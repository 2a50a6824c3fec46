// Robot descriptions built by hand that several robot tests use, each
// with the analysis its tests check against. Include after <cmocka.h>.
#pragma once

#include "robot_checks.h"

namespace robot_checks {

using K = r::Joint::Kind;

// Three boxes hanging from the world on hinges about y, x, y (the motion
// is three-dimensional).
inline r::Model chain3()
{
	r::Model m;
	m.name = "chain";
	const double mass[] = { 1.0, 1.5, 0.8 };
	const char *links[] = { "l1", "l2", "l3" };
	const char *joints[] = { "j1", "j2", "j3" };
	const r::Vec3 axes[] = { { 0, 1, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
	for (int i = 0; i < 3; i++) {
		double top = -0.5 * i;
		m.links.push_back(
			box_link(links[i], mass[i], { 0.05, 0.08, 0.5 }, pose(0, 0, top), { 0, 0, top - 0.25 }));
		m.joints.push_back(joint(joints[i], K::continuous, i ? links[i - 1] : "world", links[i],
					 pose(0, 0, top), axes[i]));
	}
	return m;
}

// A box arm along +x from a hinge about y at the origin: gravity turns it
// towards positive angles, against the upper stop.
inline r::Model stopped_arm(double lower, double upper)
{
	r::Model m;
	m.name = "arm";
	m.links.push_back(box_link("arm", 1.0, { 0.6, 0.05, 0.05 }, pose(0, 0, 0), { 0.3, 0, 0 }));
	r::Joint j = joint("hinge", K::revolute, "world", "arm", pose(0, 0, 0), { 0, 1, 0 });
	j.lower = lower;
	j.upper = upper;
	m.joints.push_back(j);
	return m;
}

// A box spinning about the vertical z axis (gravity exerts no torque about
// it): I = m (x^2 + y^2) / 12.
inline r::Model turntable(double effort_limit, double velocity_limit, double damping, double friction)
{
	r::Model m;
	m.name = "table";
	m.links.push_back(box_link("plate", 2.0, { 0.6, 0.3, 0.05 }, pose(0, 0, 0), { 0, 0, 0 }));
	r::Joint j = joint("spin", K::continuous, "world", "plate", pose(0, 0, 0), { 0, 0, 1 });
	if (effort_limit > 0)
		j.effort_limit = effort_limit;
	if (velocity_limit > 0)
		j.velocity_limit = velocity_limit;
	j.damping = damping;
	j.friction = friction;
	m.joints.push_back(j);
	return m;
}

inline constexpr double kTableI = 2.0 * (0.36 + 0.09) / 12;

// A fixed model: a floor (plane) with a mast 0.7 m high.
inline r::Model floor_and_mast()
{
	r::Model m;
	m.name = "room";
	r::Link floor = box_link("floor", 1.0, { 1, 1, 1 }, pose(0, 0, 0), { 0, 0, 0 });
	r::Collision plane;
	plane.name = "ground";
	plane.shape.kind = r::Shape::Kind::plane;
	plane.pose = pose(0, 0, 0);
	floor.collisions.push_back(plane);
	floor.self_collide = true;
	m.links.push_back(floor);
	m.links.push_back(box_link("mast", 1.0, { 0.05, 0.05, 0.7 }, pose(0, 0, 0.35), { 0, 0, 0.35 }));
	m.joints.push_back(joint("weld", K::fixed, "floor", "mast", pose(0, 0, 0.35)));
	return m;
}

} // namespace robot_checks
