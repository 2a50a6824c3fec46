// A world file's models as one robot model (robot_file.cc): in one ODE
// world they can touch each other (a robot and the ground it stands on),
// which models of their own never do. Names become <model>.<name>, every
// pose the world's, each model's links a collision group of their own
// (description.h), and a static model's links welded to the world.
#pragma once

#include "description.h"

namespace tcs::sim::robot {

Model merge_world(const Description &world);

} // namespace tcs::sim::robot
