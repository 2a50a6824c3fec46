// From a parsed scenario to what the coordinator runs: the models and the
// devices, checked against the real world's signals so that every mistake
// is reported as FILE:LINE before anything starts.
#pragma once

#include <string>
#include <vector>

#include "coordinator.h"
#include "scenario.h"

namespace tcs {

struct WorldSetup {
	std::vector<ModelInstance> models;
	std::vector<DeviceConfig> devices;
	std::vector<SensorConfig> sensors;
	WiresConfig wires; // (their devices are in `devices` too, after the others)
	int64_t step_ns = 0;
	std::vector<std::string> signal_lines; // for --list-signals
	// Its scalar joints ("<model>.<joint>", those with a .position).
	std::vector<std::string> joints;
};

Result<WorldSetup> world_setup(const Scenario &scenario);

} // namespace tcs
