// A collision mesh read from a file of tcs's own reading, STL (binary and
// ASCII) or Wavefront OBJ: Debian packages no mesh library we would add,
// and a collision shape needs triangles only. Mesh files are untrusted
// input: every count is checked against the file's size and a limit
// before anything is allocated, and a file that is truncated, claims more
// than it holds, has a vertex that is not finite or an index past its
// vertices is an error, never a crash.
//
// What is read: STL's triangles (normals ignored: the winding says which
// side is out); OBJ's `v` and `f` lines (a polygon fanned into triangles,
// `f a/b/c` and negative indices), everything else ignored (normals,
// texture coordinates, groups, materials). Other formats (Collada .dae,
// glTF, ...) are refused by name.
#pragma once

#include <string>
#include <vector>

#include "description.h"
#include "error.h"

namespace tcs::sim::robot {

// An indexed triangle mesh: exact duplicate vertices merged, triangles
// without area (two corners equal) dropped.
struct Mesh {
	std::vector<Vec3> vertices;
	std::vector<unsigned> indices; // three a triangle, wound as the file wound them
};

inline constexpr size_t kMaxMeshTriangles = 1000000;
inline constexpr size_t kMaxMeshFileBytes = 64u << 20;

// The mesh of path, each vertex multiplied by scale (per axis, finite and
// non-zero; a mirroring scale also reverses the winding, so that the
// outside stays out). Errors: "PATH: what" or "PATH:LINE: what".
Result<Mesh> load_mesh(const std::string &path, Vec3 scale);

} // namespace tcs::sim::robot
