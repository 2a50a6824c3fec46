// Checks of a robot description against what ODE can simulate, each error
// naming the element (and where the file declared it), and the tree of
// links the model is built along.
#include "robot_check.h"

#include <cmath>
#include <cstdio>
#include <set>

#include "frames.h"

namespace tcs::sim::robot {

namespace {

std::string fmt(double v)
{
	char buf[32];
	snprintf(buf, sizeof buf, "%g", v);
	return buf;
}

bool finite(const Vec3 &v)
{
	return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// A pose ODE can use: finite, and a rotation (a quaternion of any
// non-zero length, normalized where it is used).
bool valid_pose(const Pose &p)
{
	double n = p.q[0] * p.q[0] + p.q[1] * p.q[1] + p.q[2] * p.q[2] + p.q[3] * p.q[3];
	return finite(p.p) && std::isfinite(n) && n > 1e-12;
}

// The names in `names`, comma-separated, a long list cut short (a chain
// of thousands of joints must not make a message of megabytes).
template <class Map> std::string name_list(const Map &names)
{
	std::string s;
	size_t n = 0;
	for (const auto &[name, index] : names) {
		if (n == 20) {
			s += ", and " + std::to_string(names.size() - n) + " more";
			break;
		}
		s += (n++ ? ", " : "") + name;
	}
	return s.empty() ? "none" : s;
}

Status check_shape(const Collision &c, const std::string &who)
{
	const Shape &s = c.shape;
	std::string me = who + "collision '" + c.name + "': ";
	if (!valid_pose(c.pose))
		return Error{ me + "its pose is not finite" };
	if (std::isnan(c.mu) || c.mu < 0)
		return Error{ me + "friction mu must be >= 0 (got " + fmt(c.mu) + ")" };
	auto positive = [](double v) { return std::isfinite(v) && v > 0; };
	switch (s.kind) {
	case Shape::Kind::box:
		if (!positive(s.size[0]) || !positive(s.size[1]) || !positive(s.size[2]))
			return Error{ me + "a box's sizes must be positive" };
		break;
	case Shape::Kind::cylinder:
		if (!positive(s.radius) || !positive(s.length))
			return Error{ me + "a cylinder's radius and length must be positive" };
		break;
	case Shape::Kind::sphere:
		if (!positive(s.radius))
			return Error{ me + "a sphere's radius must be positive" };
		break;
	case Shape::Kind::capsule:
		if (!positive(s.radius) || !std::isfinite(s.length) || s.length < 0)
			return Error{ me + "a capsule's radius must be positive and its length >= 0" };
		break;
	case Shape::Kind::plane:
		if (!finite(s.normal) || norm(s.normal) < 1e-12)
			return Error{ me + "a plane's normal must be a finite non-zero vector" };
		break;
	case Shape::Kind::mesh:
		if (s.indices.empty() || s.indices.size() % 3 != 0)
			return Error{ me + "mesh '" + s.mesh_uri +
				      "' has no triangles (or a number of indices not a multiple of 3)" };
		for (const Vec3 &v : s.vertices)
			if (!finite(v))
				return Error{ me + "mesh '" + s.mesh_uri + "' has a vertex that is not finite" };
		for (unsigned i : s.indices)
			if (i >= s.vertices.size())
				return Error{ me + "mesh '" + s.mesh_uri + "' has an index past its vertices" };
		break;
	}
	return Ok{};
}

Status check_link(const Link &l)
{
	std::string who = at(l.where) + "link '" + l.name + "': ";
	if (!valid_pose(l.pose))
		return Error{ who + "its pose is not finite" };
	if (!valid_pose(l.inertial))
		return Error{ who + "its inertial pose is not finite" };
	for (const Collision &c : l.collisions)
		if (auto s = check_shape(c, who); !s)
			return s;
	return Ok{};
}

// What ODE's dBodySetMass needs (only for a link that gets a body).
Status check_mass(const Link &l)
{
	std::string who = at(l.where) + "link '" + l.name + "': ";
	if (!std::isfinite(l.mass) || l.mass <= 0)
		return Error{ who + "mass must be positive and finite (got " + fmt(l.mass) + " kg)" };
	const auto &i = l.inertia; // ixx iyy izz ixy ixz iyz
	for (double v : i)
		if (!std::isfinite(v))
			return Error{ who + "its inertia is not finite" };
	// Sylvester's criterion: the leading minors of a symmetric matrix
	// are all positive exactly when it is positive definite.
	double m1 = i[0];
	double m2 = i[0] * i[1] - i[3] * i[3];
	double m3 = i[0] * (i[1] * i[2] - i[5] * i[5]) - i[3] * (i[3] * i[2] - i[5] * i[4]) +
		    i[4] * (i[3] * i[5] - i[1] * i[4]);
	if (!(m1 > 0 && m2 > 0 && m3 > 0))
		return Error{ who + "its inertia (ixx " + fmt(i[0]) + ", iyy " + fmt(i[1]) + ", izz " + fmt(i[2]) +
			      ", ixy " + fmt(i[3]) + ", ixz " + fmt(i[4]) + ", iyz " + fmt(i[5]) +
			      ") is not positive definite" };
	return Ok{};
}

Status check_joint(const Joint &j)
{
	std::string who = at(j.where) + "joint '" + j.name + "': ";
	if (!valid_pose(j.pose))
		return Error{ who + "its pose is not finite" };
	if (!finite(j.axis) || norm(j.axis) < 1e-12)
		return Error{ who + "its axis must be a finite non-zero vector" };
	if (j.kind == Joint::Kind::universal) {
		if (!finite(j.axis2) || norm(j.axis2) < 1e-12)
			return Error{ who + "its axis2 must be a finite non-zero vector" };
		if (std::fabs(dot(normalized(j.axis), normalized(j.axis2))) > 1e-6)
			return Error{ who + "a universal joint's axes must be perpendicular (ODE's are)" };
	}
	for (const std::optional<double> *lim : { &j.lower, &j.upper })
		if (*lim && std::isnan(**lim))
			return Error{ who + "a limit is not a number" };
	if (j.lower && j.upper && *j.lower > *j.upper)
		return Error{ who + "its lower limit " + fmt(*j.lower) + " is above its upper limit " + fmt(*j.upper) };
	if (j.kind == Joint::Kind::revolute || j.kind == Joint::Kind::universal) {
		// ODE measures hinge angles in (-pi, pi]: a stop beyond it would
		// never be reached, or be reached at the wrong angle.
		bool wide = (!j.lower || *j.lower <= -M_PI) && (!j.upper || *j.upper >= M_PI);
		bool lo_out = j.lower && (*j.lower < -M_PI || *j.lower > M_PI);
		bool hi_out = j.upper && (*j.upper < -M_PI || *j.upper > M_PI);
		if (!wide && (lo_out || hi_out))
			return Error{
				who + "limits beyond +-pi (" + fmt(j.lower.value_or(-INFINITY)) + ", " +
				fmt(j.upper.value_or(INFINITY)) +
				") are not supported (ODE's hinge angle wraps there); use -pi..pi, or no limits"
			};
	}
	for (auto [v, what] : { std::pair{ j.damping, "damping" }, std::pair{ j.friction, "friction" } })
		if (!std::isfinite(v) || v < 0)
			return Error{ who + what + " must be >= 0 and finite (got " + fmt(v) + ")" };
	for (const std::optional<double> *lim : { &j.effort_limit, &j.velocity_limit })
		if (*lim && std::isnan(**lim))
			return Error{ who + "an effort or velocity limit is not a number" };
	return Ok{};
}

Status check_sensor(const Sensor &s, const Topology &t, const Model &m)
{
	std::string who = at(s.where) + "sensor '" + s.name + "': ";
	if (!valid_pose(s.pose))
		return Error{ who + "its pose is not finite" };
	if (s.kind == Sensor::Kind::force_torque) {
		if (!t.joint_index.count(s.joint))
			return Error{ who + "no joint '" + s.joint +
				      "' to measure (joints: " + name_list(t.joint_index) + ")" };
		if (m.is_static)
			return Error{ who + "a static model's joints carry no load to measure" };
		return Ok{};
	}
	if (!t.link_index.count(s.link))
		return Error{ who + "no link '" + s.link + "' to mount it on (links: " + name_list(t.link_index) +
			      ")" };
	if (s.kind == Sensor::Kind::ray && !(std::isfinite(s.range_min) && std::isfinite(s.range_max) &&
					     s.range_min >= 0 && s.range_max > s.range_min))
		return Error{ who + "a ray needs 0 <= range_min < range_max (got " + fmt(s.range_min) + ", " +
			      fmt(s.range_max) + ")" };
	return Ok{};
}

Status check_initial(const std::map<std::string, double> &values, const char *what, const Model &m, const Topology &t)
{
	for (const auto &[name, v] : values) {
		auto it = t.joint_index.find(name);
		if (it == t.joint_index.end())
			return Error{ std::string(what) + ": no joint '" + name + "' in model '" + m.name +
				      "' (joints: " + name_list(t.joint_index) + ")" };
		const Joint &j = m.joints[it->second];
		if (!one_dof(j.kind))
			return Error{ std::string(what) + ": joint '" + name +
				      "' is not revolute, continuous or prismatic (only those take one)" };
		if (m.is_static)
			return Error{ std::string(what) + ": joint '" + name +
				      "' is in a static model: it does not move" };
		if (!std::isfinite(v))
			return Error{ std::string(what) + ": joint '" + name + "': the value is not finite" };
	}
	return Ok{};
}

// Which links are welded to the world (Topology::anchored).
void find_anchored(const Model &m, const RobotOptions &opts, Topology &t)
{
	size_t n = m.links.size();
	t.anchored.assign(n, m.is_static);
	if (m.is_static)
		return;
	std::set<std::string> measured;
	for (const Sensor &s : m.sensors)
		if (s.kind == Sensor::Kind::force_torque)
			measured.insert(s.joint);
	auto welds = [&](size_t j) {
		return m.joints[j].kind == Joint::Kind::fixed && !measured.count(m.joints[j].name);
	};
	std::vector<size_t> todo;
	if (opts.fixed)
		todo.push_back(0);
	for (size_t j = 0; j < m.joints.size(); j++)
		if (t.joint_parent[j] < 0 && welds(j))
			todo.push_back(t.joint_child[j]);
	while (!todo.empty()) {
		size_t l = todo.back();
		todo.pop_back();
		if (t.anchored[l])
			continue;
		t.anchored[l] = true;
		for (size_t j : t.child_joints[l])
			if (welds(j))
				todo.push_back(t.joint_child[j]);
	}
}

} // namespace

std::string at(const Where &where)
{
	if (where.file.empty())
		return "";
	if (where.line <= 0)
		return where.file + ": ";
	return where.file + ":" + std::to_string(where.line) + ": ";
}

Result<Topology> check_robot(const Model &m, const RobotOptions &opts)
{
	std::string me = at(m.where) + "model '" + m.name + "': ";
	if (m.links.empty())
		return Error{ me + "it has no links" };
	if (!valid_pose(m.pose) || (opts.pose && !valid_pose(*opts.pose)))
		return Error{ me + "its pose is not finite" };
	if (!finite(opts.gravity))
		return Error{ me + "gravity is not finite" };

	Topology t;
	for (size_t i = 0; i < m.links.size(); i++) {
		const Link &l = m.links[i];
		if (l.name.empty() || l.name == "world")
			return Error{ at(l.where) + "a link cannot be named '" + l.name + "'" };
		if (!t.link_index.emplace(l.name, i).second)
			return Error{ at(l.where) + "two links are named '" + l.name + "'" };
		if (auto s = check_link(l); !s)
			return s.error();
	}
	t.child_joints.resize(m.links.size());
	for (size_t i = 0; i < m.joints.size(); i++) {
		const Joint &j = m.joints[i];
		std::string who = at(j.where) + "joint '" + j.name + "': ";
		if (j.name.empty() || !t.joint_index.emplace(j.name, i).second)
			return Error{ at(j.where) + "joint names must be unique and non-empty ('" + j.name + "')" };
		auto child = t.link_index.find(j.child);
		if (child == t.link_index.end())
			return Error{ who + "no child link '" + j.child + "'" };
		int parent = -1;
		if (j.parent != "world") {
			auto p = t.link_index.find(j.parent);
			if (p == t.link_index.end())
				return Error{ who + "no parent link '" + j.parent + "'" };
			parent = (int)p->second;
			if (p->second == child->second)
				return Error{ who + "joins link '" + j.child + "' to itself" };
			t.child_joints[p->second].push_back(i);
		}
		if (opts.fixed && child->second == 0 && j.kind != Joint::Kind::fixed)
			return Error{ who + "moves the root link '" + j.child +
				      "', which `fixed` welds to the world (drop one or the other)" };
		t.joint_parent.push_back(parent);
		t.joint_child.push_back(child->second);
		if (auto s = check_joint(j); !s)
			return s.error();
	}
	for (const Sensor &s : m.sensors)
		if (auto st = check_sensor(s, t, m); !st)
			return st.error();
	if (auto s = check_initial(opts.initial_positions, "initial_positions", m, t); !s)
		return s.error();
	if (auto s = check_initial(opts.initial_velocities, "initial_velocities", m, t); !s)
		return s.error();

	find_anchored(m, opts, t);
	for (size_t j = 0; j < m.joints.size(); j++)
		if (m.joints[j].kind != Joint::Kind::fixed && t.anchored[t.joint_child[j]] && !m.is_static)
			return Error{ at(m.joints[j].where) + "joint '" + m.joints[j].name + "' moves link '" +
				      m.joints[j].child + "', which fixed joints weld to the world" };
	for (const Sensor &s : m.sensors)
		if (s.kind == Sensor::Kind::force_torque && t.anchored[t.joint_child[t.joint_index.at(s.joint)]])
			return Error{
				at(s.where) + "sensor '" + s.name + "': joint '" + s.joint +
				"' moves a link welded to the world (the root, fixed): there is no load to measure"
			};
	for (size_t i = 0; i < m.links.size(); i++) {
		const Link &l = m.links[i];
		if (t.anchored[i])
			continue;
		if (auto s = check_mass(l); !s)
			return s.error();
		for (const Collision &c : l.collisions)
			if (c.shape.kind == Shape::Kind::plane)
				return Error{ at(l.where) + "link '" + l.name + "': collision '" + c.name +
					      "': a plane must be on a link fixed to the world (a static model, "
					      "a fixed root, or a fixed joint to the world)" };
	}
	return t;
}

} // namespace tcs::sim::robot
