// check_description: per model, names, the joint tree, then each link's
// mass and inertia.
#include "description_check.h"

#include <cmath>
#include <unordered_map>
#include <vector>

#include "robot_xml.h"

namespace tcs::sim::robot {

namespace {

std::string in_quotes(const std::string &s)
{
	return "'" + s + "'";
}

Error fault(const Where &w, const std::string &message)
{
	return at(w.file, w.line, message);
}

std::string num(double v)
{
	char b[32];
	snprintf(b, sizeof b, "%g", v);
	return b;
}

Status check_names(const Model &m)
{
	std::unordered_map<std::string, const Where *> seen;
	for (const Link &l : m.links)
		if (!seen.emplace(l.name, &l.where).second)
			return fault(l.where, "link " + in_quotes(l.name) + " is declared twice (first at line " +
						      std::to_string(seen[l.name]->line) + ")");
	seen.clear();
	for (const Joint &j : m.joints)
		if (!seen.emplace(j.name, &j.where).second)
			return fault(j.where, "joint " + in_quotes(j.name) + " is declared twice (first at line " +
						      std::to_string(seen[j.name]->line) + ")");
	seen.clear();
	for (const Sensor &s : m.sensors)
		if (!seen.emplace(s.name, &s.where).second)
			return fault(s.where, "sensor " + in_quotes(s.name) + " is declared twice (first at line " +
						      std::to_string(seen[s.name]->line) + ")");
	return Ok{};
}

// Each link the child of one joint at most, and no walk up from a link
// comes back to it.
Status check_tree(const Model &m)
{
	std::unordered_map<std::string, int> index;
	for (size_t i = 0; i < m.links.size(); i++)
		index[m.links[i].name] = (int)i;
	std::vector<int> parent_joint(m.links.size(), -1);
	for (size_t ji = 0; ji < m.joints.size(); ji++) {
		const Joint &j = m.joints[ji];
		if (j.child == "world")
			return fault(j.where, "joint " + in_quotes(j.name) + " has the world as its child: the world cannot move");
		for (const std::string *l : { &j.parent, &j.child })
			if (*l != "world" && !index.count(*l))
				return fault(j.where, "joint " + in_quotes(j.name) + " names link " + in_quotes(*l) +
							      ", which the model does not declare");
		int c = index[j.child];
		if (parent_joint[c] >= 0) {
			const Joint &first = m.joints[parent_joint[c]];
			return fault(j.where, "link " + in_quotes(j.child) + " is the child of two joints, " +
						      in_quotes(first.name) + " (line " + std::to_string(first.where.line) +
						      ") and " + in_quotes(j.name) + ": a joint loop, which tcs cannot simulate");
		}
		parent_joint[c] = (int)ji;
	}
	std::vector<char> state(m.links.size(), 0);
	for (size_t i = 0; i < m.links.size(); i++) {
		std::vector<int> path;
		int l = (int)i;
		while (l >= 0 && state[l] == 0) {
			state[l] = 1;
			path.push_back(l);
			int pj = parent_joint[l];
			l = (pj < 0 || m.joints[pj].parent == "world") ? -1 : index[m.joints[pj].parent];
		}
		if (l >= 0 && state[l] == 1) {
			const Joint &j = m.joints[parent_joint[l]];
			return fault(j.where, "the joints form a loop through link " + in_quotes(m.links[l].name) +
						      " (joint " + in_quotes(j.name) + "), which tcs cannot simulate");
		}
		for (int p : path)
			state[p] = 2;
	}
	return Ok{};
}

// Positive definite: the leading minors of the symmetric tensor.
bool positive_definite(const std::array<double, 6> &in)
{
	double xx = in[0], yy = in[1], zz = in[2], xy = in[3], xz = in[4], yz = in[5];
	double m2 = xx * yy - xy * xy;
	double det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
	return xx > 0 && m2 > 0 && det > 0;
}

Status check_masses(const Model &m)
{
	std::unordered_map<std::string, bool> welded;
	for (const Joint &j : m.joints)
		if (j.parent == "world" && j.kind == Joint::Kind::fixed)
			welded[j.child] = true;
	for (const Link &l : m.links) {
		if (!std::isfinite(l.mass) || l.mass < 0)
			return fault(l.where, "link " + in_quotes(l.name) + " has mass " + num(l.mass) +
						      ": a mass must be a finite, non-negative number");
		for (double v : l.inertia)
			if (!std::isfinite(v))
				return fault(l.where, "link " + in_quotes(l.name) + " has an inertia that is not finite");
		if (m.is_static || welded[l.name])
			continue; // it never moves: its mass plays no part
		if (l.mass == 0)
			return fault(l.where, "link " + in_quotes(l.name) + " has no mass but can move: give it a positive mass");
		if (!positive_definite(l.inertia)) {
			std::string v;
			for (double x : l.inertia)
				v += " " + num(x);
			return fault(l.where, "link " + in_quotes(l.name) + " can move but its inertia (ixx iyy izz ixy ixz iyz =" + v +
						      ") is not positive definite: ODE cannot move it");
		}
	}
	return Ok{};
}

Status check_joints(const Model &m)
{
	for (const Joint &j : m.joints)
		if (j.lower && j.upper && *j.lower > *j.upper)
			return fault(j.where, "joint " + in_quotes(j.name) + " has lower limit " + num(*j.lower) +
						      " above its upper limit " + num(*j.upper));
	return Ok{};
}

} // namespace

Status check_description(const Description &d)
{
	for (const Model &m : d.models) {
		if (m.links.empty())
			return fault(m.where, "model " + in_quotes(m.name) + " has no link");
		for (auto check : { check_names, check_tree, check_joints, check_masses }) {
			auto st = check(m);
			if (!st.ok())
				return st;
		}
	}
	return Ok{};
}

} // namespace tcs::sim::robot
