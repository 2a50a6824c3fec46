// tcs-trace plot: the TCS paper's three plots (controller time against
// simulation time, their instantaneous disparity, the aggregate relative
// timing error) and joint trajectories, rendered by gnuplot into a PNG or
// SVG image.
#pragma once

#include <string>

#include "error.h"
#include "trace_data.h"

namespace tcs {

enum class PlotKind { Timing, Disparity, Error, Joints };

// out's extension picks the image type: .png or .svg.
Status plot_trace(const TraceData &t, PlotKind kind, const std::string &out);

} // namespace tcs
