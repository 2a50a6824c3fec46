// The built-in world, used when tcs-run has no --world: docs/DESIGN.md §4's
// pendulum with its state sensor and torque actuator. It is TOML read by
// the same parser as any file, so it cannot drift from what files mean;
// scenarios/pendulum.toml is the same world, commented.
#include "default_scenario.h"

namespace tcs {

namespace {

constexpr std::string_view kDefaultScenario = R"toml([sim]
step = "1ms"
model = "pendulum"

[model]
length = 1.0
mass = 1.0
initial_angle = 0.0

[[device]]
path = "/dev/tcs/pendulum/state"
kind = "sensor"
signals = ["pendulum.hinge.position", "pendulum.hinge.velocity"]
format = "text"
mode = "stream"
rate = "1kHz"

[[device]]
path = "/dev/tcs/pendulum/torque"
kind = "actuator"
signals = ["pendulum.hinge.effort"]
format = "text"
limit = 5.0
)toml";

} // namespace

std::string_view default_scenario_text()
{
	return kDefaultScenario;
}

Result<Scenario> default_scenario()
{
	return parse_scenario_text(std::string(kDefaultScenario), "(built-in pendulum scenario)");
}

} // namespace tcs
