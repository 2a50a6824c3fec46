// tcs-trace export: a trace as CSV (one topic, one row per message, nested
// fields flattened into columns), as JSON (every message with its topic and
// time), or as Chrome Trace Event JSON (Perfetto, chrome://tracing: one track
// per controller and one for the simulation, in virtual time), or a CAN
// bus's frames as candump's log (trace_candump.cc).
#pragma once

#include <cstdio>
#include <string>

#include "error.h"

namespace tcs {

enum class ExportFormat { Csv, Json, Chrome, Candump };

// topic: only that topic's messages ("" for all; CSV needs one). Writes to out.
Status export_trace(const std::string &path, ExportFormat format, const std::string &topic, FILE *out);

} // namespace tcs
