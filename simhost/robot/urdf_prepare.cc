// prepare_urdf: the URDF's links and joints as a tree, checked with their
// lines, and the changes that let libsdformat's converter keep what the
// file means (see urdf_prepare.h).
#include "urdf_prepare.h"

#include <cmath>
#include <cstdlib>
#include <unordered_map>
#include <vector>

#include "mesh_uri.h"
#include "robot_xml.h"

namespace tcs::sim::robot {

namespace {

using tinyxml2::XMLElement;

// libsdformat's test for "no mass" (ignition::math::equal's epsilon).
constexpr double converter_zero_mass = 1e-6;

struct ULink {
	std::string name;
	XMLElement *elem = nullptr;
	bool has_mass = false;
	int parent_joint = -1;     // index into joints
	std::vector<int> children; // joint indices
};

struct UJoint {
	std::string name, type, parent, child;
	int line = 0;
};

struct Tree {
	std::vector<ULink> links;
	std::vector<UJoint> joints;
	std::unordered_map<std::string, int> link_index;
	bool world_used = false;
};

std::string in_quotes(const std::string &s)
{
	return "'" + s + "'";
}

// A number attribute that must be a finite number: std::strtod reads
// "nan" and "inf" too, which urdfdom then passes on.
Status finite_attribute(const std::string &file, const XMLElement *e, const char *attr, bool non_negative)
{
	const char *v = e->Attribute(attr);
	if (!v)
		return Ok{};
	char *end = nullptr;
	double d = std::strtod(v, &end);
	while (end && (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r'))
		end++;
	if (end == v || (end && *end != '\0'))
		return at(file, e->GetLineNum(), std::string("<") + e->Name() + " " + attr + "=\"" + v + "\">: not a number");
	if (!std::isfinite(d))
		return at(file, e->GetLineNum(), std::string("<") + e->Name() + " " + attr + "=\"" + v + "\">: not a finite number");
	if (non_negative && d < 0)
		return at(file, e->GetLineNum(), std::string("<") + e->Name() + " " + attr + "=\"" + v + "\">: a negative mass");
	return Ok{};
}

// The link's <inertial>: checked numbers, and whether the converter will
// see a mass.
Result<bool> read_mass(const std::string &file, const XMLElement *link)
{
	const XMLElement *in = link->FirstChildElement("inertial");
	if (!in)
		return false;
	const XMLElement *m = in->FirstChildElement("mass");
	if (!m)
		return false; // urdfdom refuses it, with its own words
	auto st = finite_attribute(file, m, "value", true);
	if (!st.ok())
		return st.error();
	if (const XMLElement *i = in->FirstChildElement("inertia"))
		for (const char *a : { "ixx", "iyy", "izz", "ixy", "ixz", "iyz" }) {
			auto ok = finite_attribute(file, i, a, false);
			if (!ok.ok())
				return ok.error();
		}
	return std::fabs(m->DoubleAttribute("value", 0)) > converter_zero_mass;
}

// urdfdom knows box, cylinder, sphere and mesh, and drops a collision
// of any other shape without failing. A mesh's file is found now, where
// its line is known (see urdf_prepare.h).
Status check_collisions(const std::string &file, XMLElement *link, UrdfFacts &facts)
{
	for (XMLElement *c = link->FirstChildElement("collision"); c; c = c->NextSiblingElement("collision")) {
		XMLElement *g = c->FirstChildElement("geometry");
		XMLElement *s = g ? g->FirstChildElement() : nullptr;
		if (!s)
			return at(file, c->GetLineNum(), "a <collision> without a <geometry> shape");
		std::string kind = s->Name();
		if (kind == "mesh") {
			const char *uri = s->Attribute("filename");
			if (!uri || !*uri)
				return at(file, s->GetLineNum(), "a <mesh> without a filename");
			auto path = resolve_mesh_uri(uri, file);
			if (!path.ok())
				return at(file, s->GetLineNum(), path.error().message);
			facts.meshes.emplace(*path, UrdfFacts::MeshRef{ uri, s->GetLineNum() });
			s->SetAttribute("filename", path->c_str());
			continue;
		}
		if (kind != "box" && kind != "cylinder" && kind != "sphere")
			return at(file, s->GetLineNum(), "URDF has no <" + kind + "> geometry (box, cylinder, sphere, mesh)");
	}
	return Ok{};
}

const char *link_attr(const XMLElement *joint, const char *which)
{
	const XMLElement *e = joint->FirstChildElement(which);
	return e ? e->Attribute("link") : nullptr;
}

Result<Tree> read_tree(const std::string &file, XMLElement *robot, UrdfFacts &facts)
{
	Tree t;
	for (XMLElement *e = robot->FirstChildElement("link"); e; e = e->NextSiblingElement("link")) {
		const char *name = e->Attribute("name");
		if (!name || !*name)
			return at(file, e->GetLineNum(), "a <link> without a name");
		if (t.link_index.count(name))
			return at(file, e->GetLineNum(), "link " + in_quotes(name) + " is declared twice (first at line " +
								 std::to_string(facts.link_line[name]) + ")");
		auto mass = read_mass(file, e);
		if (!mass.ok())
			return mass.error();
		auto shapes = check_collisions(file, e, facts);
		if (!shapes.ok())
			return shapes.error();
		t.link_index[name] = (int)t.links.size();
		t.links.push_back(ULink{ name, e, *mass, -1, {} });
		facts.link_line[name] = e->GetLineNum();
	}
	for (XMLElement *e = robot->FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) {
		const char *name = e->Attribute("name");
		const char *type = e->Attribute("type");
		int line = e->GetLineNum();
		if (!name || !*name)
			return at(file, line, "a <joint> without a name");
		if (facts.joint_line.count(name))
			return at(file, line, "joint " + in_quotes(name) + " is declared twice (first at line " +
						      std::to_string(facts.joint_line[name]) + ")");
		std::string ty = type ? type : "";
		if (ty == "floating" || ty == "planar")
			return at(file, line, "tcs cannot simulate joint type " + ty + " (joint " + in_quotes(name) + ")");
		if (ty != "revolute" && ty != "continuous" && ty != "prismatic" && ty != "fixed")
			return at(file, line, "joint " + in_quotes(name) + " has unknown type \"" + ty + "\"");
		const char *parent = link_attr(e, "parent");
		const char *child = link_attr(e, "child");
		if (!parent || !child)
			return at(file, line, "joint " + in_quotes(name) + " lacks a <" + (parent ? "child" : "parent") +
						      " link=\"...\">");
		facts.joint_line[name] = line;
		facts.joint_type[name] = ty;
		t.joints.push_back(UJoint{ name, ty, parent, child, line });
	}
	return t;
}

// Parents and children by index; world, when used but undeclared, is
// declared (as the first link, so that it is the converter's root).
Status link_up(const std::string &file, XMLElement *robot, Tree &t, UrdfFacts &facts)
{
	for (const UJoint &j : t.joints) {
		if (j.child == "world")
			return at(file, j.line, "joint " + in_quotes(j.name) + " has the world as its child: the world cannot move");
		if (j.parent == "world" && !t.link_index.count("world")) {
			XMLElement *w = robot->GetDocument()->NewElement("link");
			w->SetAttribute("name", "world");
			robot->InsertFirstChild(w);
			t.link_index["world"] = (int)t.links.size();
			t.links.push_back(ULink{ "world", w, false, -1, {} });
		}
		for (const std::string *l : { &j.parent, &j.child })
			if (!t.link_index.count(*l))
				return at(file, j.line, "joint " + in_quotes(j.name) + " names link " + in_quotes(*l) +
								", which the file does not declare");
	}
	for (int ji = 0; ji < (int)t.joints.size(); ji++) {
		const UJoint &j = t.joints[ji];
		ULink &c = t.links[t.link_index[j.child]];
		if (c.parent_joint >= 0) {
			const UJoint &first = t.joints[c.parent_joint];
			return at(file, j.line, "link " + in_quotes(j.child) + " is the child of two joints, " +
							in_quotes(first.name) + " (line " + std::to_string(first.line) + ") and " +
							in_quotes(j.name) + ": a joint loop, which tcs cannot simulate");
		}
		c.parent_joint = ji;
		t.links[t.link_index[j.parent]].children.push_back(ji);
		if (j.parent == "world")
			t.world_used = true;
	}
	// Every link has at most one parent now: a loop is a walk up that
	// comes back. Each link is walked once (state 2: known to end).
	std::vector<char> state(t.links.size(), 0);
	for (size_t i = 0; i < t.links.size(); i++) {
		std::vector<int> path;
		int l = (int)i;
		while (l >= 0 && state[l] == 0) {
			state[l] = 1;
			path.push_back(l);
			int pj = t.links[l].parent_joint;
			l = pj < 0 ? -1 : t.link_index[t.joints[pj].parent];
		}
		if (l >= 0 && state[l] == 1) {
			const UJoint &j = t.joints[t.links[l].parent_joint];
			return at(file, j.line, "the joints form a loop through link " + in_quotes(t.links[l].name) +
							" (joint " + in_quotes(j.name) + "), which tcs cannot simulate");
		}
		for (int p : path)
			state[p] = 2;
	}
	std::vector<int> roots;
	for (size_t i = 0; i < t.links.size(); i++)
		if (t.links[i].parent_joint < 0)
			roots.push_back((int)i);
	if (roots.size() > 1) {
		const ULink &a = t.links[roots[0]], &b = t.links[roots[1]];
		return at(file, b.elem->GetLineNum(), "links " + in_quotes(a.name) + " (line " + std::to_string(a.elem->GetLineNum()) +
							      ") and " + in_quotes(b.name) +
							      " are both roots: no joint joins them");
	}
	return Ok{};
}

bool lumped(const Tree &t, const ULink &l)
{
	if (l.parent_joint < 0)
		return false;
	const UJoint &j = t.joints[l.parent_joint];
	return j.type == "fixed" && j.parent != "world";
}

// Whether l or a link fixed to it (transitively) has mass; the first
// moving joint they carry, through `carried`.
bool fixed_group_mass(const Tree &t, int l, int &carried)
{
	bool mass = t.links[l].has_mass;
	for (int ji : t.links[l].children) {
		const UJoint &j = t.joints[ji];
		if (j.type != "fixed") {
			if (carried < 0)
				carried = ji;
			continue;
		}
		mass = fixed_group_mass(t, t.link_index.at(j.child), carried) || mass;
	}
	return mass;
}

// Replaces the link's <inertial> (a mass of 0, or none) with one the
// converter keeps.
void give_stand_in_inertial(XMLElement *link)
{
	while (XMLElement *old = link->FirstChildElement("inertial"))
		link->DeleteChild(old);
	tinyxml2::XMLDocument *d = link->GetDocument();
	XMLElement *in = d->NewElement("inertial");
	XMLElement *m = d->NewElement("mass");
	m->SetAttribute("value", 1.0);
	XMLElement *i = d->NewElement("inertia");
	for (const char *a : { "ixx", "iyy", "izz" })
		i->SetAttribute(a, 1.0);
	for (const char *a : { "ixy", "ixz", "iyz" })
		i->SetAttribute(a, 0.0);
	in->InsertEndChild(m);
	in->InsertEndChild(i);
	link->InsertFirstChild(in);
}

Status mend_massless(const std::string &file, XMLElement *robot, Tree &t, UrdfFacts &facts)
{
	size_t n = t.links.size();
	for (size_t i = 0; i < n; i++) {
		ULink &l = t.links[i];
		if (l.name == "world" || l.has_mass)
			continue;
		int line = l.elem->GetLineNum();
		int carried = -1;
		if (lumped(t, l)) {
			fixed_group_mass(t, (int)i, carried);
			if (carried >= 0)
				return at(file, line, "link " + in_quotes(l.name) + " has no mass and is fixed to " +
							      in_quotes(t.joints[l.parent_joint].parent) +
							      ": libsdformat's URDF conversion would drop joint " +
							      in_quotes(t.joints[carried].name) +
							      " beyond it; give it an <inertial> with a small mass");
			continue;
		}
		if (fixed_group_mass(t, (int)i, carried))
			continue; // the converter lumps a mass fixed to it into it
		if (l.parent_joint >= 0 && t.joints[l.parent_joint].type != "fixed")
			return at(file, line, "link " + in_quotes(l.name) + " has no mass but moves (joint " +
						      in_quotes(t.joints[l.parent_joint].name) + " is " +
						      t.joints[l.parent_joint].type + "): give it an <inertial> with a positive mass");
		// A fixed base: the root, or welded to the world.
		give_stand_in_inertial(l.elem);
		facts.massless.insert(l.name);
		if (l.parent_joint >= 0)
			continue;
		tinyxml2::XMLDocument *d = robot->GetDocument();
		if (!t.link_index.count("world")) {
			XMLElement *w = d->NewElement("link");
			w->SetAttribute("name", "world");
			robot->InsertFirstChild(w);
		}
		std::string name = "world_to_" + l.name;
		while (facts.joint_line.count(name))
			name += "_";
		XMLElement *j = d->NewElement("joint");
		j->SetAttribute("name", name.c_str());
		j->SetAttribute("type", "fixed");
		XMLElement *p = d->NewElement("parent");
		p->SetAttribute("link", "world");
		XMLElement *c = d->NewElement("child");
		c->SetAttribute("link", l.name.c_str());
		j->InsertEndChild(p);
		j->InsertEndChild(c);
		robot->InsertEndChild(j);
		facts.weld = name;
		facts.joint_line[name] = line;
		facts.joint_type[name] = "fixed";
	}
	return Ok{};
}

} // namespace

Result<UrdfFacts> prepare_urdf(const std::string &file, tinyxml2::XMLDocument &doc)
{
	UrdfFacts facts;
	XMLElement *robot = doc.RootElement();
	auto t = read_tree(file, robot, facts);
	if (!t.ok())
		return t.error();
	if (t->links.empty())
		return at(file, robot->GetLineNum(), "the robot has no <link>");
	auto st = link_up(file, robot, *t, facts);
	if (!st.ok())
		return st.error();
	st = mend_massless(file, robot, *t, facts);
	if (!st.ok())
		return st.error();
	for (XMLElement *g = robot->FirstChildElement("gazebo"); g; g = g->NextSiblingElement("gazebo"))
		for (XMLElement *s = g->FirstChildElement("sensor"); s; s = s->NextSiblingElement("sensor"))
			if (const char *name = s->Attribute("name"))
				facts.sensor_line.emplace(name, s->GetLineNum());
	return facts;
}

} // namespace tcs::sim::robot
