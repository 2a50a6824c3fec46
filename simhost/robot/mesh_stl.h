// An STL file (binary or ASCII, mesh_stl.cc) as a triangle soup, for load_mesh
// (mesh_load.h), which scales and indexes it.
#pragma once

#include <string>
#include <string_view>

#include "error.h"
#include "mesh_text.h"

namespace tcs::sim::robot {

// bytes: the whole file; path for messages ("PATH: what", "PATH:LINE:
// what").
Result<Soup> read_stl(const std::string &path, std::string_view bytes);

} // namespace tcs::sim::robot
