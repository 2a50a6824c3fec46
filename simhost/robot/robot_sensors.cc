// IMU, force-torque, contact and ray sensors.
//
// The IMU's acceleration is the mount point's velocity differenced over
// the step: ODE's integrator advances velocities by exactly a*dt (symplectic
// Euler), so the difference is the acceleration the step applied, every
// force and constraint included, where summing forces would miss the
// constraint forces of joints without feedback.
#include "robot_sensors.h"

#include <algorithm>
#include <cmath>

#include "frames.h"

namespace tcs::sim::robot {

namespace {

const SensorField kImu[] = {
	{ "orientation", 4, "quaternion" },
	{ "angular_velocity", 3, "rad/s" },
	{ "linear_acceleration", 3, "m/s^2" },
};
const SensorField kForceTorque[] = { { "force", 3, "N" }, { "torque", 3, "N*m" } };
const SensorField kContact[] = { { "count", 1, "1" }, { "force", 3, "N" } };
const SensorField kRay[] = { { "range", 1, "m" } };

size_t offset(Sensor::Kind kind, size_t field)
{
	size_t o = 0;
	auto fields = sensor_fields(kind);
	for (size_t f = 0; f < field; f++)
		o += fields[f].width;
	return o;
}

void put(std::vector<double> &values, size_t at, const Vec3 &v)
{
	std::copy(v.begin(), v.end(), values.begin() + (ptrdiff_t)at);
}

} // namespace

std::span<const SensorField> sensor_fields(Sensor::Kind kind)
{
	switch (kind) {
	case Sensor::Kind::imu:
		return kImu;
	case Sensor::Kind::force_torque:
		return kForceTorque;
	case Sensor::Kind::contact:
		return kContact;
	case Sensor::Kind::ray:
		break;
	}
	return kRay;
}

Sensors::~Sensors()
{
	for (Item &s : items_)
		if (s.ray)
			dGeomDestroy(s.ray);
}

void Sensors::add(const Sensor &desc, const Model &model, const Topology &topo, const std::vector<RobotLink> &links,
		  const RobotJoints &joints, Collider &collider, const Pose &model_in_world)
{
	Item s;
	s.kind = desc.kind;
	if (desc.kind == Sensor::Kind::force_torque) {
		size_t j = topo.joint_index.at(desc.joint);
		s.link = topo.joint_child[j];
		s.joint = joints.ode[j];
		auto it = std::find_if(measured_.begin(), measured_.end(),
				       [&](const auto &m) { return m.first == s.joint; });
		if (it != measured_.end()) {
			s.fb = it->second;
		} else {
			s.fb = &feedback_.emplace_back();
			measured_.push_back({ s.joint, s.fb });
			dJointSetFeedback(s.joint, s.fb);
		}
		for (const RobotJoints::Moving &m : joints.moving)
			if (!m.universal && joints.one[m.index].name() == desc.joint)
				s.joint1 = &joints.one[m.index];
		// The anchor in the child's frame (the joint rides on the child:
		// the same local point in the zero and the initial pose).
		Pose child0 =
			compose(model_in_world, { model.links[s.link].pose.p, normalized(model.links[s.link].pose.q) });
		Vec3 anchor0 = robot::add(model_in_world.p, rotate(model_in_world.q, model.joints[j].pose.p));
		s.anchor = unrotate(child0.q, sub(anchor0, child0.p));
	} else {
		s.link = topo.link_index.at(desc.link);
		Pose link_in_model{ model.links[s.link].pose.p, normalized(model.links[s.link].pose.q) };
		s.mount = compose(inverse(link_in_model), { desc.pose.p, normalized(desc.pose.q) });
	}
	if (desc.kind == Sensor::Kind::contact)
		collider.sense(s.link);
	if (desc.kind == Sensor::Kind::ray) {
		s.range_min = desc.range_min;
		s.range_max = desc.range_max;
		s.ray = dCreateRay(nullptr, desc.range_max - desc.range_min);
		dGeomRaySetClosestHit(s.ray, 1);
	}
	size_t width = 0;
	for (const SensorField &f : sensor_fields(desc.kind))
		width += f.width;
	s.values.assign(width, 0);
	if (desc.kind == Sensor::Kind::imu)
		s.last_v = point_velocity(links[s.link], compose(link_pose(links[s.link]), s.mount).p);
	items_.push_back(std::move(s));
}

void Sensors::update_imu(Item &s, double dt, const RobotLink &link)
{
	Pose at = compose(link_pose(link), s.mount);
	Vec3 v = point_velocity(link, at.p);
	Vec3 a = dt > 0 ? scale(sub(v, s.last_v), 1 / dt) : Vec3{ 0, 0, 0 };
	s.last_v = v;
	std::copy(at.q.begin(), at.q.end(), s.values.begin());
	put(s.values, 4, unrotate(at.q, angular_velocity(link)));
	// What an accelerometer reads: the acceleration less gravity's.
	put(s.values, 7, unrotate(at.q, sub(a, gravity_)));
}

void Sensors::update_force_torque(Item &s, const RobotLink &link)
{
	Pose child = link_pose(link);
	Vec3 anchor = robot::add(child.p, rotate(child.q, s.anchor));
	Vec3 com = to_vec(dBodyGetPosition(link.body));
	Vec3 f = to_vec(s.fb->f1); // on body1, the child
	// ODE's torque is about the child's centre of mass.
	Vec3 t = robot::add(to_vec(s.fb->t1), cross(sub(com, anchor), f));
	if (s.joint1) {
		// The effort and damping ODE was given as explicit forces: the
		// joint carries them too, though they are not constraint forces.
		dVector3 axis;
		if (dJointGetType(s.joint) == dJointTypeHinge) {
			dJointGetHingeAxis(s.joint, axis);
			t = robot::add(t, scale(to_vec(axis), s.joint1->added()));
		} else {
			dJointGetSliderAxis(s.joint, axis);
			f = robot::add(f, scale(to_vec(axis), s.joint1->added()));
		}
	}
	put(s.values, 0, unrotate(child.q, f));
	put(s.values, 3, unrotate(child.q, t));
}

void Sensors::update(double dt, const std::vector<RobotLink> &links, const Collider &collider)
{
	for (Item &s : items_) {
		const RobotLink &link = links[s.link];
		switch (s.kind) {
		case Sensor::Kind::imu:
			update_imu(s, dt, link);
			break;
		case Sensor::Kind::force_torque:
			if (dt > 0)
				update_force_torque(s, link);
			break;
		case Sensor::Kind::contact:
			s.values[0] = collider.contact_count(s.link);
			put(s.values, 1, collider.contact_force(s.link));
			break;
		case Sensor::Kind::ray: {
			Pose at = compose(link_pose(link), s.mount);
			Vec3 dir = rotate(at.q, { 1, 0, 0 });
			Vec3 start = robot::add(at.p, scale(dir, s.range_min));
			dGeomRaySet(s.ray, start[0], start[1], start[2], dir[0], dir[1], dir[2]);
			double d = collider.cast(s.ray, s.link);
			s.values[0] = std::isfinite(d) ? s.range_min + d : s.range_max;
			break;
		}
		}
	}
}

void Sensors::read(size_t i, size_t field, double *out) const
{
	const Item &s = items_[i];
	size_t o = offset(s.kind, field);
	uint32_t w = sensor_fields(s.kind)[field].width;
	std::copy(s.values.begin() + (ptrdiff_t)o, s.values.begin() + (ptrdiff_t)(o + w), out);
}

} // namespace tcs::sim::robot
