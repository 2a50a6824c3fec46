// What scenario.h promises of an accepted scenario's wires ([[can]],
// [[serial]], [[i2c]] and the devices on them), checked by scenario_fuzz on
// every scenario the parser accepts: ranges, ids and paths unique, a
// frame's fields within its payload and apart, one driver an effort. A
// broken promise aborts (tcs_fuzz::check).
#pragma once

#include <string>
#include <vector>

#include "scenario.h"

namespace scenario_wire_promises {

// Checks s's wires, and adds to *known the world's signals that their names
// need (a joint's three, a link's two, a field's signal without its index),
// for the check against a world's signals.
void check_wires(const tcs::Scenario &s, std::vector<std::string> *known);

} // namespace scenario_wire_promises
