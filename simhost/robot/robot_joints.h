// A robot's joints as ODE joints: made with the bodies in the description's
// zero pose (ODE measures angles and positions from the pose it is made
// in), then the bodies moved to the initial positions and velocities; and
// the work they need at each step (held efforts, damping).
//
// Every ODE joint is attached child first (ODE's body1 is the child link):
// joint feedback's first force is then the one on the child.
#pragma once

#include <string>
#include <vector>

#include <ode/ode.h>

#include "description.h"
#include "error.h"
#include "joint1.h"
#include "ode_robot.h"
#include "robot_check.h"
#include "robot_links.h"

namespace tcs::sim::robot {

// A universal joint as its signals see it: two angles, 0 about the
// description's `axis` (fixed in the parent), 1 about `axis2` (fixed in the
// child), with efforts held, saturated and damped as Joint1 does.
class Universal {
public:
	Universal(std::string name, dJointID joint, double damping)
		: name_(std::move(name)), joint_(joint), damping_(damping)
	{}

	const std::string &name() const { return name_; }
	double position(int i) const;
	double velocity(int i) const;
	double effort(int i) const { return applied_[i]; }
	void command(const double e[2])
	{
		commanded_[0] = e[0];
		commanded_[1] = e[1];
	}
	void limit(double effort, double velocity)
	{
		effort_limit_ = effort;
		velocity_limit_ = velocity;
	}
	void apply();

private:
	std::string name_;
	dJointID joint_;
	double damping_;
	double effort_limit_ = INFINITY, velocity_limit_ = INFINITY;
	double commanded_[2] = { 0, 0 };
	double applied_[2] = { 0, 0 };
};

// A ball joint's damping: a torque against the child's angular velocity
// relative to the parent's.
struct BallDamping {
	dBodyID child, parent; // parent null: the world
	double damping;
	void apply() const;
};

struct RobotJoints {
	// The joints with signals, in the description's order.
	struct Moving {
		bool universal; // index into `two`, else into `one`
		size_t index;
	};
	std::vector<Joint1> one; // revolute, continuous, prismatic
	std::vector<Universal> two;
	std::vector<BallDamping> balls;
	std::vector<Moving> moving;
	std::vector<dJointID> ode; // per description joint; null when a weld made it needless
	// An upper bound on the constraint rows of the joints (ODE's exact
	// stepper costs the cube of a connected group's rows).
	size_t rows = 0;

	// Before a step: efforts and damping into ODE's accumulators.
	void apply();
	// After a step: the hinge angles' turns.
	void update();
};

// The links are in their zero pose at rest; leaves them in the initial one.
RobotJoints make_joints(dWorldID world, const Model &desc, const Topology &topo, const std::vector<RobotLink> &links,
			const Pose &model_in_world, const RobotOptions &opts);

} // namespace tcs::sim::robot
