// A robot's sensors, computed after every step from the bodies, the
// joints' feedback and the collision geometry (ode_robot.h lists their
// signals and frames).
#pragma once

#include <deque>
#include <span>
#include <vector>

#include <ode/ode.h>

#include "description.h"
#include "robot_check.h"
#include "robot_collide.h"
#include "robot_joints.h"
#include "robot_links.h"

namespace tcs::sim::robot {

struct SensorField {
	const char *name;
	uint32_t width;
	const char *unit;
};

// A kind's signals, in their order.
std::span<const SensorField> sensor_fields(Sensor::Kind kind);

class Sensors {
public:
	Sensors(const Vec3 &gravity) : gravity_(gravity) {}
	~Sensors();
	Sensors(const Sensors &) = delete;
	Sensors &operator=(const Sensors &) = delete;

	// The bodies are in their initial state; check_robot has checked the
	// sensor's link and joint exist.
	void add(const Sensor &desc, const Model &model, const Topology &topo, const std::vector<RobotLink> &links,
		 const RobotJoints &joints, Collider &collider, const Pose &model_in_world);
	// After a step of dt seconds (0: the initial state, nothing moved).
	void update(double dt, const std::vector<RobotLink> &links, const Collider &collider);
	// Field `field` (sensor_fields' index) of sensor `i`.
	void read(size_t i, size_t field, double *out) const;

private:
	struct Item {
		Sensor::Kind kind;
		size_t link;
		Pose mount; // the sensor frame in the link frame
		Vec3 last_v{ 0, 0, 0 }; // imu: the mount point's velocity after the last step
		dJointFeedback *fb = nullptr; // force_torque
		dJointID joint = nullptr;
		const Joint1 *joint1 = nullptr; // force_torque on a hinge or slider: its effort
		Vec3 anchor{ 0, 0, 0 }; // force_torque: the joint's anchor in the link frame
		dGeomID ray = nullptr;
		double range_min = 0, range_max = 0;
		std::vector<double> values; // the fields, one after the other
	};

	void update_imu(Item &s, double dt, const RobotLink &link);
	void update_force_torque(Item &s, const RobotLink &link);

	Vec3 gravity_;
	std::vector<Item> items_;
	std::deque<dJointFeedback> feedback_; // one per measured joint: ODE keeps a pointer
	std::vector<std::pair<dJointID, dJointFeedback *>> measured_;
};

} // namespace tcs::sim::robot
