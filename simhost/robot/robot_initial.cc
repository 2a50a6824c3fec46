// Initial positions as rigid motions of joints' child subtrees, then
// initial velocities as the sum of the joints' velocity fields (taken in
// the final pose, so positions first, velocities after).
#include "robot_initial.h"

#include <algorithm>

#include "frames.h"

namespace tcs::sim::robot {

namespace {

// The links on the child side of joint `j` (its child and everything
// joined below it), each once even in a closed loop.
std::vector<size_t> subtree(const Topology &t, size_t j)
{
	std::vector<bool> seen(t.anchored.size(), false);
	std::vector<size_t> out, todo{ t.joint_child[j] };
	while (!todo.empty()) {
		size_t l = todo.back();
		todo.pop_back();
		if (seen[l])
			continue;
		seen[l] = true;
		out.push_back(l);
		for (size_t c : t.child_joints[l])
			todo.push_back(t.joint_child[c]);
	}
	return out;
}

// The joints in order of their parent's depth below the world (a root
// link, or the world itself, first).
std::vector<size_t> root_first(const Topology &t)
{
	size_t n = t.anchored.size();
	std::vector<size_t> depth(n, SIZE_MAX);
	std::vector<bool> is_child(n, false);
	for (size_t j = 0; j < t.joint_child.size(); j++)
		if (t.joint_parent[j] >= 0)
			is_child[t.joint_child[j]] = true;
	std::vector<size_t> frontier;
	for (size_t l = 0; l < n; l++)
		if (!is_child[l]) {
			depth[l] = 0;
			frontier.push_back(l);
		}
	for (size_t d = 1; !frontier.empty(); d++) {
		std::vector<size_t> next;
		for (size_t l : frontier)
			for (size_t j : t.child_joints[l])
				if (depth[t.joint_child[j]] == SIZE_MAX) {
					depth[t.joint_child[j]] = d;
					next.push_back(t.joint_child[j]);
				}
		frontier.swap(next);
	}
	std::vector<size_t> order(t.joint_child.size());
	for (size_t j = 0; j < order.size(); j++)
		order[j] = j;
	auto key = [&](size_t j) { return t.joint_parent[j] < 0 ? 0 : depth[(size_t)t.joint_parent[j]] + 1; };
	std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
	return order;
}

// The joint's anchor and axis in the world now (ODE keeps both relative to
// the bodies, so they have followed every move so far).
void anchor_axis(dJointID j, bool hinge, Vec3 &anchor, Vec3 &axis)
{
	dVector3 a, x;
	if (hinge) {
		dJointGetHingeAnchor(j, a);
		dJointGetHingeAxis(j, x);
		anchor = to_vec(a);
	} else {
		dJointGetSliderAxis(j, x);
		anchor = { 0, 0, 0 };
	}
	axis = to_vec(x);
}

void turn(dBodyID b, const Vec3 &pivot, const Quat &r)
{
	Vec3 p = add(pivot, rotate(r, sub(to_vec(dBodyGetPosition(b)), pivot)));
	dBodySetPosition(b, p[0], p[1], p[2]);
	dQuaternion q;
	to_ode(normalized(qmul(r, to_quat(dBodyGetQuaternion(b)))), q);
	dBodySetQuaternion(b, q);
}

} // namespace

void place_initial(const Model &desc, const Topology &topo, const std::vector<RobotLink> &links,
		   const std::vector<dJointID> &joints, const RobotOptions &opts)
{
	if (opts.initial_positions.empty() && opts.initial_velocities.empty())
		return;
	std::vector<size_t> order = root_first(topo);
	for (size_t j : order) {
		auto it = opts.initial_positions.find(desc.joints[j].name);
		if (it == opts.initial_positions.end() || !joints[j] || it->second == 0)
			continue;
		bool hinge = desc.joints[j].kind != Joint::Kind::prismatic;
		Vec3 anchor, axis;
		anchor_axis(joints[j], hinge, anchor, axis);
		double q = it->second;
		Quat r{ std::cos(q / 2), 0, 0, 0 };
		for (int k = 0; k < 3; k++)
			r[1 + k] = std::sin(q / 2) * axis[k];
		for (size_t l : subtree(topo, j)) {
			dBodyID b = links[l].body;
			if (!b)
				continue;
			if (hinge) {
				turn(b, anchor, r);
			} else {
				Vec3 p = add(to_vec(dBodyGetPosition(b)), scale(axis, q));
				dBodySetPosition(b, p[0], p[1], p[2]);
			}
		}
	}
	for (size_t j : order) {
		auto it = opts.initial_velocities.find(desc.joints[j].name);
		if (it == opts.initial_velocities.end() || !joints[j] || it->second == 0)
			continue;
		bool hinge = desc.joints[j].kind != Joint::Kind::prismatic;
		Vec3 anchor, axis;
		anchor_axis(joints[j], hinge, anchor, axis);
		Vec3 rate = scale(axis, it->second);
		for (size_t l : subtree(topo, j)) {
			dBodyID b = links[l].body;
			if (!b)
				continue;
			Vec3 v = to_vec(dBodyGetLinearVel(b));
			if (hinge) {
				Vec3 w = add(to_vec(dBodyGetAngularVel(b)), rate);
				dBodySetAngularVel(b, w[0], w[1], w[2]);
				v = add(v, cross(rate, sub(to_vec(dBodyGetPosition(b)), anchor)));
			} else {
				v = add(v, rate);
			}
			dBodySetLinearVel(b, v[0], v[1], v[2]);
		}
	}
}

} // namespace tcs::sim::robot
