// Where a robot file's mesh URI points on this machine, found as ROS and
// Gazebo find it, without either installed:
//  - a relative path: against the robot file's folder; file://PATH: PATH
//    (absolute, or relative as above); an absolute path as it is;
//  - package://PKG/REST: PKG/REST in each folder of ROS_PACKAGE_PATH
//    (colon-separated; a folder that is itself named PKG counts too), in
//    share/ of each prefix of AMENT_PREFIX_PATH (ROS 2), then the robot
//    file's ancestors: a folder named PKG above it (the usual layout
//    PKG/urdf/robot.urdf beside PKG/meshes/);
//  - model://NAME/REST: NAME/REST in each folder of GZ_SIM_RESOURCE_PATH,
//    IGN_GAZEBO_RESOURCE_PATH, SDF_PATH and GAZEBO_MODEL_PATH, then a
//    folder named NAME above the robot file.
// The first regular file found wins.
#pragma once

#include <string>

#include "error.h"

namespace tcs::sim::robot {

// The path of uri's file, or "mesh 'URI' not found (looked in: ...)" (the
// caller puts the robot file's FILE:LINE before it); other schemes
// (http://, ...) are refused by name.
Result<std::string> resolve_mesh_uri(const std::string &uri, const std::string &robot_file);

} // namespace tcs::sim::robot
