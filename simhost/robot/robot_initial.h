// A robot's initial state: the child side of each joint given an initial
// position or velocity moved rigidly so that the joint reads it.
#pragma once

#include <vector>

#include <ode/ode.h>

#include "description.h"
#include "ode_robot.h"
#include "robot_check.h"
#include "robot_links.h"

namespace tcs::sim::robot {

// `joints` are the ODE joints per description joint (null: none), made
// with the links in their zero pose at rest. Root side first, so that a
// joint is turned about where its parent's joints have already put it.
void place_initial(const Model &desc, const Topology &topo, const std::vector<RobotLink> &links,
		   const std::vector<dJointID> &joints, const RobotOptions &opts);

} // namespace tcs::sim::robot
