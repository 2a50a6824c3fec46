// tcs-run --list-signals: what a scenario offers a controller, its signals,
// its devices and its wires, printed on stdout.
#pragma once

#include <string>

#include "world_setup.h"

namespace tcs {

// world_file names the scenario ("": the built-in one).
void print_signals(const std::string &world_file, const WorldSetup &setup);

} // namespace tcs
