// ODE joints from the description's: kinds, anchors and axes, stops,
// friction as a motor held at zero velocity, actuator limits; and the
// universal and ball joints' per-step efforts and damping.
#include "robot_joints.h"

#include <algorithm>
#include <cmath>

#include "frames.h"
#include "robot_initial.h"

namespace tcs::sim::robot {

namespace {

// ODE's dParamX, dParamX2, dParamX3 are spaced by this.
constexpr int kAxisParams = dParamGroup;

double effort_limit(const Joint &j)
{
	return j.effort_limit && *j.effort_limit > 0 ? *j.effort_limit : INFINITY;
}

double velocity_limit(const Joint &j)
{
	return j.velocity_limit && *j.velocity_limit > 0 ? *j.velocity_limit : INFINITY;
}

// Stops and friction on one axis of a joint, through the joint kind's
// parameter setter. Returns the constraint rows they may add.
size_t set_stops_and_friction(void (*set)(dJointID, int, dReal), dJointID j, int axis, const Joint &d, bool stops)
{
	size_t rows = 0;
	int base = axis * kAxisParams;
	if (stops && (d.lower || d.upper)) {
		// The upper first: ODE ignores a low stop set above the
		// current high one (and the default high one is infinite, so
		// the order only matters when replacing both).
		set(j, dParamHiStop + base, d.upper.value_or(dInfinity));
		set(j, dParamLoStop + base, d.lower.value_or(-dInfinity));
		set(j, dParamBounce + base, 0);
		rows = 1;
	}
	if (d.friction > 0) {
		// Coulomb friction as ODE's motor: it holds the joint at zero
		// velocity with any effort up to `friction`, and slips at it.
		set(j, dParamVel + base, 0);
		set(j, dParamFMax + base, d.friction);
		rows = 1; // a limited, powered axis shares one row
	}
	return rows;
}

void attach(dJointID j, const std::vector<RobotLink> &links, const Topology &t, size_t i)
{
	int p = t.joint_parent[i];
	dJointAttach(j, links[t.joint_child[i]].body, p < 0 ? nullptr : links[(size_t)p].body);
}

dJointID make_ball_friction(dWorldID world, dJointID ball, double friction)
{
	// Three motors at zero velocity about the child's own axes: friction
	// up to `friction` about each (a box, not a cone, of torques).
	dJointID m = dJointCreateAMotor(world, nullptr);
	dJointAttach(m, dJointGetBody(ball, 0), dJointGetBody(ball, 1));
	dJointSetAMotorMode(m, dAMotorUser);
	dJointSetAMotorNumAxes(m, 3);
	dBodyID child = dJointGetBody(ball, 0);
	const dReal *R = dBodyGetRotation(child);
	for (int a = 0; a < 3; a++) {
		// Column a of R: the child's axis a in the world.
		dJointSetAMotorAxis(m, a, 1, R[a], R[4 + a], R[8 + a]);
		dJointSetAMotorParam(m, dParamVel + a * kAxisParams, 0);
		dJointSetAMotorParam(m, dParamFMax + a * kAxisParams, friction);
	}
	return m;
}

// Sets a universal joint's axes (ODE's 1 and 2). ODE recomputes the
// joint's reference rotation from both axes at each call, and complains
// (on stderr) when they are parallel at that moment: its defaults are x
// and y, so an axis 1 along y must wait until axis 2 has moved away.
void set_universal_axes(dJointID j, const Vec3 &a1, const Vec3 &a2)
{
	dVector3 c1, c2;
	dJointGetUniversalAxis1(j, c1);
	dJointGetUniversalAxis2(j, c2);
	if (std::fabs(dot(a1, to_vec(c2))) > 0.999) {
		// Perpendicular to a1 and to the current axis 1.
		Vec3 t = normalized(cross(a1, to_vec(c1)));
		dJointSetUniversalAxis2(j, t[0], t[1], t[2]);
	}
	dJointSetUniversalAxis1(j, a1[0], a1[1], a1[2]);
	dJointSetUniversalAxis2(j, a2[0], a2[1], a2[2]);
}

} // namespace

double Universal::position(int i) const
{
	// ODE's axis 1 is on body1, the child: the description's axis2.
	return i == 0 ? dJointGetUniversalAngle2(joint_) : dJointGetUniversalAngle1(joint_);
}

double Universal::velocity(int i) const
{
	return i == 0 ? dJointGetUniversalAngle2Rate(joint_) : dJointGetUniversalAngle1Rate(joint_);
}

void Universal::apply()
{
	double f[2];
	for (int i = 0; i < 2; i++) {
		double v = velocity(i);
		applied_[i] = std::clamp(commanded_[i], -effort_limit_, effort_limit_);
		if ((applied_[i] > 0 && v >= velocity_limit_) || (applied_[i] < 0 && v <= -velocity_limit_))
			applied_[i] = 0;
		f[i] = applied_[i] - damping_ * v;
	}
	dJointAddUniversalTorques(joint_, f[1], f[0]);
}

void BallDamping::apply() const
{
	const dReal *wc = dBodyGetAngularVel(child);
	Vec3 w = to_vec(wc);
	if (parent)
		w = sub(w, to_vec(dBodyGetAngularVel(parent)));
	Vec3 t = scale(w, -damping);
	dBodyAddTorque(child, t[0], t[1], t[2]);
	if (parent)
		dBodyAddTorque(parent, -t[0], -t[1], -t[2]);
}

void RobotJoints::apply()
{
	for (Joint1 &j : one)
		j.apply();
	for (Universal &u : two)
		u.apply();
	for (const BallDamping &b : balls)
		b.apply();
}

void RobotJoints::update()
{
	for (Joint1 &j : one)
		j.update();
}

RobotJoints make_joints(dWorldID world, const Model &desc, const Topology &topo, const std::vector<RobotLink> &links,
			const Pose &model_in_world, const RobotOptions &opts)
{
	RobotJoints out;
	out.ode.assign(desc.joints.size(), nullptr);
	if (desc.is_static)
		return out;
	for (size_t i = 0; i < desc.joints.size(); i++) {
		const Joint &d = desc.joints[i];
		if (!links[topo.joint_child[i]].body)
			continue; // welded to the world with its child
		Vec3 anchor = add(model_in_world.p, rotate(model_in_world.q, d.pose.p));
		Vec3 axis = rotate(model_in_world.q, normalized(d.axis));
		dJointID j = nullptr;
		switch (d.kind) {
		case Joint::Kind::revolute:
		case Joint::Kind::continuous: {
			j = dJointCreateHinge(world, nullptr);
			attach(j, links, topo, i);
			dJointSetHingeAnchor(j, anchor[0], anchor[1], anchor[2]);
			dJointSetHingeAxis(j, axis[0], axis[1], axis[2]);
			// A revolute joint limited to all of -pi..pi is a
			// continuous one (robot_check rejects other wide ones).
			bool all_round = (!d.lower || *d.lower <= -M_PI) && (!d.upper || *d.upper >= M_PI);
			bool stops = d.kind == Joint::Kind::revolute && !all_round;
			out.rows += 5 + set_stops_and_friction(dJointSetHingeParam, j, 0, d, stops);
			break;
		}
		case Joint::Kind::prismatic:
			j = dJointCreateSlider(world, nullptr);
			attach(j, links, topo, i);
			dJointSetSliderAxis(j, axis[0], axis[1], axis[2]);
			out.rows += 5 + set_stops_and_friction(dJointSetSliderParam, j, 0, d, true);
			break;
		case Joint::Kind::fixed:
			j = dJointCreateFixed(world, nullptr);
			attach(j, links, topo, i);
			dJointSetFixed(j);
			out.rows += 6;
			break;
		case Joint::Kind::ball:
			j = dJointCreateBall(world, nullptr);
			attach(j, links, topo, i);
			dJointSetBallAnchor(j, anchor[0], anchor[1], anchor[2]);
			out.rows += 3;
			if (d.friction > 0) {
				make_ball_friction(world, j, d.friction);
				out.rows += 3;
			}
			if (d.damping > 0)
				out.balls.push_back({ dJointGetBody(j, 0), dJointGetBody(j, 1), d.damping });
			break;
		case Joint::Kind::universal: {
			Vec3 axis2 = rotate(model_in_world.q, normalized(d.axis2));
			j = dJointCreateUniversal(world, nullptr);
			attach(j, links, topo, i);
			dJointSetUniversalAnchor(j, anchor[0], anchor[1], anchor[2]);
			set_universal_axes(j, axis2, axis);
			out.rows += 4 + set_stops_and_friction(dJointSetUniversalParam, j, 1, d, d.lower || d.upper);
			if (d.friction > 0) {
				Joint no_stops = d;
				no_stops.lower = no_stops.upper = std::nullopt;
				out.rows += set_stops_and_friction(dJointSetUniversalParam, j, 0, no_stops, false);
			}
			break;
		}
		}
		out.ode[i] = j;
	}

	place_initial(desc, topo, links, out.ode, opts);

	for (size_t i = 0; i < desc.joints.size(); i++) {
		const Joint &d = desc.joints[i];
		dJointID j = out.ode[i];
		if (!j)
			continue;
		if (one_dof(d.kind)) {
			auto kind = d.kind == Joint::Kind::prismatic ? Joint1::Kind::slider : Joint1::Kind::hinge;
			auto q = opts.initial_positions.find(d.name);
			double initial = q == opts.initial_positions.end() ? 0 : q->second;
			Joint1 j1(d.name, kind, j, true, d.damping, initial);
			j1.limit(effort_limit(d), velocity_limit(d));
			out.moving.push_back({ false, out.one.size() });
			out.one.push_back(std::move(j1));
		} else if (d.kind == Joint::Kind::universal) {
			Universal u(d.name, j, d.damping);
			u.limit(effort_limit(d), velocity_limit(d));
			out.moving.push_back({ true, out.two.size() });
			out.two.push_back(std::move(u));
		}
	}
	return out;
}

} // namespace tcs::sim::robot
