// Link bodies: the mass and full inertia tensor turned from the inertial
// frame into the body's, and the link frame read back from the body.
#include "robot_links.h"

#include "frames.h"

namespace tcs::sim::robot {

RobotLink make_link(dWorldID world, const Link &desc, const Pose &model_in_world, bool anchored)
{
	RobotLink l;
	l.name = desc.name;
	Pose link{ desc.pose.p, normalized(desc.pose.q) };
	Pose inertial{ desc.inertial.p, normalized(desc.inertial.q) };
	Pose in_world = compose(model_in_world, link);
	if (anchored) {
		l.fixed_pose = in_world;
		return l;
	}
	// The inertial frame seen from the link frame: its origin is the
	// centre of mass, its rotation turns the tensor into the body's axes
	// (dMassRotate: I' = R I R^T).
	Pose rel = compose(inverse(link), inertial);
	l.com = rel.p;
	const auto &i = desc.inertia; // ixx iyy izz ixy ixz iyz
	dMass m;
	dMassSetParameters(&m, desc.mass, 0, 0, 0, i[0], i[1], i[2], i[3], i[4], i[5]);
	dMatrix3 R;
	to_ode_matrix(rel.q, R);
	dMassRotate(&m, R);

	l.body = dBodyCreate(world);
	dBodySetMass(l.body, &m);
	Vec3 c = add(in_world.p, rotate(in_world.q, l.com));
	dBodySetPosition(l.body, c[0], c[1], c[2]);
	dQuaternion q;
	to_ode(in_world.q, q);
	dBodySetQuaternion(l.body, q);
	if (!desc.gravity)
		dBodySetGravityMode(l.body, 0);
	return l;
}

Pose link_pose(const RobotLink &l)
{
	if (!l.body)
		return l.fixed_pose;
	Quat q = to_quat(dBodyGetQuaternion(l.body));
	return { sub(to_vec(dBodyGetPosition(l.body)), rotate(q, l.com)), q };
}

Vec3 point_velocity(const RobotLink &l, const Vec3 &p)
{
	if (!l.body)
		return { 0, 0, 0 };
	dVector3 v;
	dBodyGetPointVel(l.body, p[0], p[1], p[2], v);
	return to_vec(v);
}

Vec3 angular_velocity(const RobotLink &l)
{
	return l.body ? to_vec(dBodyGetAngularVel(l.body)) : Vec3{ 0, 0, 0 };
}

void read_link_pose(const RobotLink &l, double out[7])
{
	Pose p = link_pose(l);
	for (int i = 0; i < 3; i++)
		out[i] = p.p[i];
	for (int i = 0; i < 4; i++)
		out[3 + i] = p.q[i];
}

void read_link_twist(const RobotLink &l, double out[6])
{
	Vec3 v = point_velocity(l, link_pose(l).p);
	Vec3 w = angular_velocity(l);
	for (int i = 0; i < 3; i++) {
		out[i] = v[i];
		out[3 + i] = w[i];
	}
}

} // namespace tcs::sim::robot
