// Who drives each effort: an actuator [[device]], a CAN motor, a command
// frame's field or a serial servo. A joint takes its effort from one of
// them only (two would overwrite each other step by step), so each wire's
// parser asks here before it claims one.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "scenario.h"

namespace tcs::scenario_parse {

// What already drives `effort` in the scenario read so far, with the line
// of its claim ("/dev/a (line 6)", "motor 0x001 on can0 (line 9)"); nullopt
// if nothing does. `effort` may carry an index ("arm.u.effort[1]": a
// universal joint's second axis), which meets the whole signal and the
// same index, not another index.
std::optional<std::string> effort_driver(const Scenario &sc, std::string_view effort);

} // namespace tcs::scenario_parse
