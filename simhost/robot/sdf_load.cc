// load_robot_file: the file read and checked as XML (robot_xml), a URDF
// mended (urdf_prepare), libsdformat's load, and its DOM copied into the
// plain description, every pose resolved in the model's frame, then
// checked (description_check). The one file that includes sdformat's
// headers.
#include "sdf_load.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>

#include <sdf/sdf.hh>

#include "description_check.h"
#include "robot_mesh.h"
#include "robot_xml.h"
#include "urdf_prepare.h"
#include "urdfdom_messages.h"
#include "xml_facts.h"

namespace tcs::sim::robot {

namespace {

namespace im = ignition::math;

// SDF's "no limit" is +-1e16; files also write +-1.79769e+308.
constexpr double no_limit = 1e16;

void silence_libsdformat()
{
	static std::once_flag once;
	std::call_once(once, [] { sdf::Console::Instance()->SetQuiet(true); });
}

Vec3 vec(const im::Vector3d &v)
{
	return { v.X(), v.Y(), v.Z() };
}

Pose pose(const im::Pose3d &p)
{
	return { vec(p.Pos()), { p.Rot().W(), p.Rot().X(), p.Rot().Y(), p.Rot().Z() } };
}

// The pose b, given in frame a, in a's parent frame: composed by hand, for
// ignition-math 6's Pose3 product reads right to left.
im::Pose3d compose(const im::Pose3d &a, const im::Pose3d &b)
{
	return im::Pose3d(a.Pos() + a.Rot().RotateVector(b.Pos()), a.Rot() * b.Rot());
}

Pose compose(const Pose &a, const im::Pose3d &b)
{
	im::Pose3d pa(a.p[0], a.p[1], a.p[2], a.q[0], a.q[1], a.q[2], a.q[3]);
	return pose(compose(pa, b));
}

// What the conversion needs besides the DOM: the file as the user named
// it, and for a URDF the facts its own text gave.
struct Ctx {
	const std::string &file;
	const UrdfFacts *urdf; // null for SDF
	int robot_line;        // URDF's <robot>
};

Where where(const Ctx &c, const sdf::ElementPtr &e, const std::map<std::string, int> *urdf_lines,
	    const std::string &name)
{
	if (c.urdf) {
		auto it = urdf_lines->find(name);
		return { c.file, it == urdf_lines->end() ? 0 : it->second };
	}
	return { c.file, e ? e->LineNumber().value_or(0) : 0 };
}

std::string in_quotes(const std::string &s)
{
	return "'" + s + "'";
}

// A pose in the model's frame, or the resolver's error at w.
Result<Pose> in_model(const sdf::SemanticPose &sp, const Where &w, const std::string &what)
{
	im::Pose3d p;
	sdf::Errors errs = sp.Resolve(p, "__model__");
	if (!errs.empty())
		return at(w.file, w.line, "cannot place " + what + ": " + one_line(errs[0].Message()));
	return pose(p);
}

// An optional child's value: FindElement is null when the file lacks it.
std::optional<double> child_double(sdf::ElementPtr e, std::initializer_list<const char *> path)
{
	for (const char *name : path) {
		if (!e || !e->HasElement(name))
			return std::nullopt;
		e = e->FindElement(name);
	}
	return e ? std::optional<double>(e->Get<double>()) : std::nullopt;
}

Result<Shape> shape(const Ctx &c, const sdf::Geometry &g, const Where &w, const std::string &col)
{
	Shape s;
	switch (g.Type()) {
	case sdf::GeometryType::BOX:
		s.kind = Shape::Kind::box;
		s.size = vec(g.BoxShape()->Size());
		return s;
	case sdf::GeometryType::CYLINDER:
		s.kind = Shape::Kind::cylinder;
		s.radius = g.CylinderShape()->Radius();
		s.length = g.CylinderShape()->Length();
		return s;
	case sdf::GeometryType::SPHERE:
		s.kind = Shape::Kind::sphere;
		s.radius = g.SphereShape()->Radius();
		return s;
	case sdf::GeometryType::CAPSULE:
		s.kind = Shape::Kind::capsule;
		s.radius = g.CapsuleShape()->Radius();
		s.length = g.CapsuleShape()->Length();
		return s;
	case sdf::GeometryType::PLANE:
		s.kind = Shape::Kind::plane;
		s.normal = vec(g.PlaneShape()->Normal().Normalized());
		return s;
	case sdf::GeometryType::MESH:
		if (!g.MeshShape()->Submesh().empty())
			return at(w.file, w.line, "collision " + in_quotes(col) + ": tcs cannot take submesh " +
							  in_quotes(g.MeshShape()->Submesh()) + " out of mesh " +
							  in_quotes(g.MeshShape()->Uri()) + ": give the collision a mesh file of its own");
		// An SDF's relative URI is against the file that declared it.
		return collision_mesh(g.MeshShape()->Uri(), vec(g.MeshShape()->Scale()),
				      g.MeshShape()->FilePath().empty() ? c.file : g.MeshShape()->FilePath(), c.urdf, w, col);
	case sdf::GeometryType::HEIGHTMAP:
		return at(w.file, w.line, "tcs cannot simulate heightmaps (collision " + in_quotes(col) + ")");
	case sdf::GeometryType::ELLIPSOID:
		return at(w.file, w.line, "tcs cannot simulate ellipsoids (collision " + in_quotes(col) + ")");
	default:
		return at(w.file, w.line, "collision " + in_quotes(col) + " has no geometry tcs knows");
	}
}

// joint_pose: the joint's, in the model's frame, for a joint's sensor.
Status add_sensor(const Ctx &c, const sdf::Sensor &s, const std::string &link, const std::string &joint,
		  const std::optional<Pose> &joint_pose, Model &m)
{
	Sensor out;
	out.name = s.Name();
	out.link = link;
	out.joint = joint;
	out.where = where(c, s.Element(), c.urdf ? &c.urdf->sensor_line : nullptr, s.Name());
	switch (s.Type()) {
	case sdf::SensorType::IMU:
		out.kind = Sensor::Kind::imu;
		break;
	case sdf::SensorType::FORCE_TORQUE:
		out.kind = Sensor::Kind::force_torque;
		break;
	case sdf::SensorType::CONTACT:
		out.kind = Sensor::Kind::contact;
		break;
	case sdf::SensorType::LIDAR:
	case sdf::SensorType::GPU_LIDAR:
		out.kind = Sensor::Kind::ray;
		if (const sdf::Lidar *l = s.LidarSensor()) {
			out.range_min = l->RangeMin();
			out.range_max = l->RangeMax();
		}
		break;
	default:
		return Ok{}; // no signal for it in tcs (sdf_load.h)
	}
	if (out.kind == Sensor::Kind::force_torque && joint.empty())
		return at(out.where.file, out.where.line,
			  "force_torque sensor " + in_quotes(out.name) + " must be inside a <joint>");
	if (joint_pose) {
		// libsdformat 12 gives a joint's sensors no pose graph: their pose
		// is relative to the joint's frame, composed here.
		if (!s.PoseRelativeTo().empty())
			return at(out.where.file, out.where.line, "sensor " + in_quotes(out.name) +
									  ": tcs cannot resolve relative_to on a joint's sensor");
		out.pose = compose(*joint_pose, s.RawPose());
	} else {
		auto p = in_model(s.SemanticPose(), out.where, "sensor " + in_quotes(out.name));
		if (!p.ok())
			return p.error();
		out.pose = *p;
	}
	out.rate_hz = s.UpdateRate();
	m.sensors.push_back(std::move(out));
	return Ok{};
}

Status add_link(const Ctx &c, const sdf::Model &sm, const sdf::Link &sl, Model &m)
{
	Link l;
	l.name = sl.Name();
	l.where = where(c, sl.Element(), c.urdf ? &c.urdf->link_line : nullptr, l.name);
	auto p = in_model(sl.SemanticPose(), l.where, "link " + in_quotes(l.name));
	if (!p.ok())
		return p.error();
	l.pose = *p;
	im::Pose3d lp;
	(void)sl.SemanticPose().Resolve(lp, "__model__");
	const im::Inertiald &in = sl.Inertial();
	l.mass = in.MassMatrix().Mass();
	l.inertial = pose(compose(lp, in.Pose())); // given in the link's frame
	const im::Vector3d d = in.MassMatrix().DiagonalMoments(), o = in.MassMatrix().OffDiagonalMoments();
	l.inertia = { d.X(), d.Y(), d.Z(), o.X(), o.Y(), o.Z() };
	if (c.urdf && c.urdf->massless.count(l.name)) {
		l.mass = 0; // the stand-in inertial urdf_prepare gave it
		l.inertia = { 0, 0, 0, 0, 0, 0 };
		l.inertial = l.pose;
	}
	auto sc = child_double(sl.Element(), { "self_collide" });
	l.self_collide = sc ? *sc != 0 : sm.SelfCollide();
	if (sl.Element() && sl.Element()->HasElement("gravity"))
		l.gravity = sl.Element()->Get<bool>("gravity");
	for (uint64_t i = 0; i < sl.CollisionCount(); i++) {
		const sdf::Collision *sc2 = sl.CollisionByIndex(i);
		Collision col;
		col.name = sc2->Name();
		Where cw = c.urdf ? l.where : Where{ c.file, sc2->Element()->LineNumber().value_or(0) };
		auto cp = in_model(sc2->SemanticPose(), cw, "collision " + in_quotes(col.name));
		if (!cp.ok())
			return cp.error();
		col.pose = *cp;
		if (sc2->Geom()->Type() == sdf::GeometryType::EMPTY)
			continue; // <empty/>: nothing to collide with
		auto s = shape(c, *sc2->Geom(), cw, col.name);
		if (!s.ok())
			return s.error();
		col.shape = std::move(*s);
		if (auto mu = child_double(sc2->Element(), { "surface", "friction", "ode", "mu" }))
			col.mu = *mu;
		l.collisions.push_back(std::move(col));
	}
	m.links.push_back(std::move(l));
	for (uint64_t i = 0; i < sl.SensorCount(); i++) {
		auto st = add_sensor(c, *sl.SensorByIndex(i), sl.Name(), "", std::nullopt, m);
		if (!st.ok())
			return st;
	}
	return Ok{};
}

Result<Joint::Kind> joint_kind(const Ctx &c, const sdf::Joint &sj, const Where &w)
{
	if (c.urdf) {
		auto t = c.urdf->joint_type.find(sj.Name());
		if (t != c.urdf->joint_type.end() && t->second == "continuous")
			return Joint::Kind::continuous;
	}
	switch (sj.Type()) {
	case sdf::JointType::REVOLUTE:
		return Joint::Kind::revolute;
	case sdf::JointType::CONTINUOUS:
		return Joint::Kind::continuous;
	case sdf::JointType::PRISMATIC:
		return Joint::Kind::prismatic;
	case sdf::JointType::FIXED:
		return Joint::Kind::fixed;
	case sdf::JointType::BALL:
		return Joint::Kind::ball;
	case sdf::JointType::UNIVERSAL:
		return Joint::Kind::universal;
	default:
		break;
	}
	std::string type = sj.Element() && sj.Element()->HasAttribute("type")
				   ? sj.Element()->Get<std::string>("type")
				   : "unknown";
	return at(w.file, w.line, "tcs cannot simulate joint type " + type + " (joint " + in_quotes(sj.Name()) + ")");
}

Result<Vec3> axis_in_model(const sdf::JointAxis *a, const Where &w, const std::string &joint)
{
	im::Vector3d v;
	sdf::Errors errs = a->ResolveXyz(v, "__model__");
	if (!errs.empty())
		return at(w.file, w.line, "cannot resolve the axis of joint " + in_quotes(joint) + ": " +
						  one_line(errs[0].Message()));
	if (!std::isfinite(v.Length()) || v.Length() == 0)
		return at(w.file, w.line, "joint " + in_quotes(joint) + " has no usable axis");
	return vec(v.Normalized());
}

// A limit the file set: finite and within SDF's "no limit".
std::optional<double> bound(double v)
{
	return std::isfinite(v) && std::fabs(v) < no_limit ? std::optional<double>(v) : std::nullopt;
}

std::optional<double> positive(double v)
{
	return std::isfinite(v) && v > 0 ? std::optional<double>(v) : std::nullopt;
}

Status add_joint(const Ctx &c, const sdf::Joint &sj, Model &m)
{
	Joint j;
	j.name = sj.Name();
	j.where = where(c, sj.Element(), c.urdf ? &c.urdf->joint_line : nullptr, j.name);
	auto kind = joint_kind(c, sj, j.where);
	if (!kind.ok())
		return kind.error();
	j.kind = *kind;
	// SDF lets a joint name a frame; the link it is attached to counts.
	if (!sj.ResolveParentLink(j.parent).empty())
		j.parent = sj.ParentLinkName();
	if (!sj.ResolveChildLink(j.child).empty())
		j.child = sj.ChildLinkName();
	auto p = in_model(sj.SemanticPose(), j.where, "joint " + in_quotes(j.name));
	if (!p.ok())
		return p.error();
	j.pose = *p;
	if (const sdf::JointAxis *a = sj.Axis(0); a && j.kind != Joint::Kind::fixed && j.kind != Joint::Kind::ball) {
		auto ax = axis_in_model(a, j.where, j.name);
		if (!ax.ok())
			return ax.error();
		j.axis = *ax;
		if (j.kind == Joint::Kind::revolute || j.kind == Joint::Kind::prismatic) {
			j.lower = bound(a->Lower());
			j.upper = bound(a->Upper());
		}
		j.effort_limit = positive(a->Effort());
		j.velocity_limit = positive(a->MaxVelocity());
		j.damping = a->Damping();
		j.friction = a->Friction();
	}
	if (const sdf::JointAxis *a2 = sj.Axis(1); a2 && j.kind == Joint::Kind::universal) {
		auto ax = axis_in_model(a2, j.where, j.name);
		if (!ax.ok())
			return ax.error();
		j.axis2 = *ax;
	}
	m.joints.push_back(j);
	for (uint64_t i = 0; i < sj.SensorCount(); i++) {
		auto st = add_sensor(c, *sj.SensorByIndex(i), j.child, j.name, j.pose, m);
		if (!st.ok())
			return st;
	}
	return Ok{};
}

Result<Model> convert_model(const Ctx &c, const sdf::Model &sm, bool in_world)
{
	Model m;
	m.name = sm.Name();
	m.is_static = sm.Static();
	m.where = c.urdf ? Where{ c.file, c.robot_line } : Where{ c.file, sm.Element()->LineNumber().value_or(0) };
	if (sm.ModelCount() > 0 || sm.InterfaceModelCount() > 0)
		return at(m.where.file, m.where.line, "tcs cannot simulate nested models (model " + in_quotes(m.name) + ")");
	im::Pose3d mp = sm.RawPose();
	if (in_world)
		(void)sm.SemanticPose().Resolve(mp, "world");
	m.pose = pose(mp);
	for (uint64_t i = 0; i < sm.LinkCount(); i++) {
		auto st = add_link(c, sm, *sm.LinkByIndex(i), m);
		if (!st.ok())
			return st.error();
	}
	// The canonical link first (description.h: links[0] is the root).
	if (const sdf::Link *canon = sm.CanonicalLink())
		for (size_t i = 1; i < m.links.size(); i++)
			if (m.links[i].name == canon->Name()) {
				std::rotate(m.links.begin(), m.links.begin() + (long)i, m.links.begin() + (long)i + 1);
				break;
			}
	for (uint64_t i = 0; i < sm.JointCount(); i++) {
		auto st = add_joint(c, *sm.JointByIndex(i), m);
		if (!st.ok())
			return st.error();
	}
	return m;
}

// libsdformat's first error, with its line.
// libsdformat 12 gives many errors no line, and a URDF's lines are those
// of the SDF it was converted to: then the line of the link or joint the
// message names.
Error sdf_error(const Ctx &c, const XmlFacts &xf, const sdf::Errors &errs, const std::string &urdfdom)
{
	if (!urdfdom.empty())
		return at(c.file, line_named(xf, urdfdom), one_line(urdfdom));
	const sdf::Error &e = errs[0];
	int line = c.urdf ? 0 : e.LineNumber().value_or(0);
	if (line == 0)
		line = line_named(xf, e.Message());
	std::string more = errs.size() > 1 ? " (and " + std::to_string(errs.size() - 1) + " more)" : "";
	return at(c.file, line, one_line(e.Message()) + more);
}

Result<Description> convert(const Ctx &c, const sdf::Root &root)
{
	Description d;
	d.file = c.file;
	if (const sdf::Model *sm = root.Model()) {
		auto m = convert_model(c, *sm, false);
		if (!m.ok())
			return m.error();
		d.models.push_back(std::move(*m));
	}
	if (root.WorldCount() > 1)
		return at(c.file, 0, "the file holds " + std::to_string(root.WorldCount()) + " worlds; tcs loads one");
	if (root.WorldCount() == 1) {
		const sdf::World *w = root.WorldByIndex(0);
		sdf::ElementPtr we = w->Element();
		if (we && we->HasElement("gravity"))
			d.gravity = vec(w->Gravity());
		if (we && we->HasElement("physics") && w->PhysicsDefault())
			d.max_step_s = w->PhysicsDefault()->MaxStepSize();
		for (uint64_t i = 0; i < w->ModelCount(); i++) {
			auto m = convert_model(c, *w->ModelByIndex(i), true);
			if (!m.ok())
				return m.error();
			d.models.push_back(std::move(*m));
		}
	}
	if (d.models.empty())
		return at(c.file, 0, "the file holds no <model>");
	return d;
}

} // namespace

Result<Description> load_robot_file(const std::string &path)
{
	silence_libsdformat();
	auto x = read_robot_xml(path);
	if (!x.ok())
		return x.error();
	auto xf = read_xml_facts(path, *x->doc);
	if (!xf.ok())
		return xf.error();
	std::optional<UrdfFacts> facts;
	sdf::Root root;
	sdf::Errors errs;
	std::string urdfdom;
	if (x->format == RobotFormat::urdf) {
		auto f = prepare_urdf(path, *x->doc);
		if (!f.ok())
			return f.error();
		facts = std::move(*f);
		tinyxml2::XMLPrinter printer;
		x->doc->Print(&printer);
		UrdfdomMessages messages;
		errs = root.LoadSdfString(printer.CStr());
		urdfdom = messages.first_error();
	} else {
		// Absolute: libsdformat looks a relative name up in its own
		// folders first, where world.sdf, model.sdf and link.sdf are its
		// schema's files.
		std::error_code ec;
		std::filesystem::path abs = std::filesystem::absolute(path, ec);
		errs = root.Load(ec ? path : abs.string());
	}
	Ctx c{ path, facts ? &*facts : nullptr, x->doc->RootElement()->GetLineNum() };
	if (!errs.empty())
		return sdf_error(c, *xf, errs, urdfdom);
	auto d = convert(c, root);
	if (!d.ok())
		return d.error();
	auto st = check_description(*d);
	if (!st.ok())
		return st.error();
	return d;
}

} // namespace tcs::sim::robot
