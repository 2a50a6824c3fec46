// A collision's mesh, found and loaded for the description: the step
// between a robot file's <mesh> (as libsdformat gives it) and the mesh
// reader, kept apart from sdf_load.cc so that it needs no sdformat.
#pragma once

#include <string>

#include "description.h"
#include "error.h"
#include "urdf_prepare.h"

namespace tcs::sim::robot {

// The shape of collision `col` at w: uri resolved against base_file's
// folder (mesh_uri.h), or, for a URDF (urdf non-null), the path
// urdf_prepare wrote in its place, reported with the URI and line the
// file gave. Errors: "FILE:LINE: mesh 'URI' not found ...", "FILE:LINE:
// collision 'C', mesh 'URI': MESHFILE: what".
Result<Shape> collision_mesh(const std::string &uri, Vec3 scale, const std::string &base_file, const UrdfFacts *urdf,
			     Where w, const std::string &col);

} // namespace tcs::sim::robot
