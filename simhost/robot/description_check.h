// What a description must be for tcs to simulate it, checked on the plain
// data whatever file it came from: names unique, joints between declared
// links forming a tree, masses and inertias a body can have. The first
// fault is returned as "FILE:LINE: message" (the line of the link or joint
// at fault).
#pragma once

#include "description.h"
#include "error.h"

namespace tcs::sim::robot {

Status check_description(const Description &d);

} // namespace tcs::sim::robot
