// collision_mesh: a URDF's mesh mapped back to what its file wrote, an
// SDF's resolved here, then loaded into the shape.
#include "robot_mesh.h"

#include "mesh_load.h"
#include "mesh_uri.h"
#include "robot_xml.h"

namespace tcs::sim::robot {

Result<Shape> collision_mesh(const std::string &uri_in, Vec3 scale, const std::string &base_file,
			     const UrdfFacts *urdf, Where w, const std::string &col)
{
	std::string uri = uri_in, path;
	if (urdf) {
		auto it = urdf->meshes.find(uri);
		if (it == urdf->meshes.end())
			return at(w.file, w.line, "collision '" + col + "': mesh '" + uri + "' lost in libsdformat's conversion");
		path = uri;
		uri = it->second.uri;
		w.line = it->second.line;
	} else {
		auto p = resolve_mesh_uri(uri, base_file);
		if (!p.ok())
			return at(w.file, w.line, p.error().message);
		path = *p;
	}
	auto mesh = load_mesh(path, scale);
	if (!mesh.ok())
		return at(w.file, w.line, "collision '" + col + "', mesh '" + uri + "': " + mesh.error().message);
	Shape s;
	s.kind = Shape::Kind::mesh;
	s.vertices = std::move(mesh->vertices);
	s.indices = std::move(mesh->indices);
	s.mesh_uri = uri;
	return s;
}

} // namespace tcs::sim::robot
