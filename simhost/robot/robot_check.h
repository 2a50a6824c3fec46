// What ODE can take from a robot description, checked before anything is
// built (a hand-written or hostile description must give an error naming
// the culprit, never a crash or a NaN), and the description's links and
// joints as a tree.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "description.h"
#include "error.h"
#include "ode_robot.h"

namespace tcs::sim::robot {

struct Topology {
	std::map<std::string, size_t> link_index;
	std::map<std::string, size_t> joint_index;
	std::vector<int> joint_parent; // per joint: its parent link, -1 for the world
	std::vector<size_t> joint_child;
	std::vector<std::vector<size_t>> child_joints; // per link: the joints it is the parent of
	// Per link: welded to the world, so it gets no ODE body (its geoms
	// stay put). The model's links when it is static, the root when the
	// options fix it, and what fixed joints weld to those or to the world
	// (unless a force-torque sensor measures that joint: it needs one).
	std::vector<bool> anchored;
};

// "FILE:LINE: " (or "FILE: ", or nothing) before a message about what was
// declared there.
std::string at(const Where &where);

Result<Topology> check_robot(const Model &model, const RobotOptions &opts);

// Whether a joint moves with one degree of freedom (signals, initial
// positions, Joint1).
inline bool one_dof(Joint::Kind k)
{
	return k == Joint::Kind::revolute || k == Joint::Kind::continuous || k == Joint::Kind::prismatic;
}

} // namespace tcs::sim::robot
