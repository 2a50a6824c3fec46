// tcs-trace export --format candump: a trace's CAN frames as candump's log.
#pragma once

#include <cstdio>
#include <string>

#include "error.h"

namespace tcs {

// The CAN frames of topic (a /tcs/wire/ topic of a CAN interface; "" for
// every one), one candump log line each, in time order.
Status export_candump(const std::string &path, const std::string &topic, FILE *out);

} // namespace tcs
