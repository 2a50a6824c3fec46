// read_obj: a Wavefront OBJ's `v` and `f` lines. A face's corners are
// `v`, `v/vt`, `v//vn` or `v/vt/vn`; only v is used, 1-based, or negative
// (counted back from the last vertex read so far). A polygon is fanned
// from its first corner, which is right for the convex faces exporters
// write.
#include "mesh_obj.h"

#include <cstdint>

#include "mesh_load.h"
#include "robot_xml.h"

namespace tcs::sim::robot {

namespace {

// Three corners a triangle: a file of one big face cannot make more
// vertices count than this many triangles could use.
constexpr size_t max_vertices = 3 * kMaxMeshTriangles;

// A corner's vertex, as an index into the vertices read so far.
Result<size_t> corner(const std::string &path, int line, std::string_view w, size_t have)
{
	std::string_view v = w.substr(0, w.find('/'));
	int64_t i = 0;
	auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), i);
	if (ec != std::errc() || end != v.data() + v.size() || v.empty())
		return at(path, line, "a face corner " + quoted(w) + " is not a vertex index");
	if (i > 0 && (uint64_t)i <= have)
		return (size_t)(i - 1);
	if (i < 0 && (uint64_t)(-(i + 1)) < have) // -1: the last
		return (size_t)((int64_t)have + i);
	return at(path, line, "a face corner " + quoted(w) + " is past the " + std::to_string(have) +
				      " vertices read so far");
}

} // namespace

Result<Soup> read_obj(const std::string &path, std::string_view bytes)
{
	std::vector<Vec3> vertices;
	Soup soup;
	Words text(bytes);
	std::vector<std::string_view> w;
	std::vector<size_t> face;
	while (text.next_line(w)) {
		if (w.empty())
			continue;
		int line = text.line();
		if (w[0] == "v") {
			// x y z, then an optional w or r g b, unused.
			if (w.size() < 4)
				return at(path, line, "a vertex needs 3 numbers");
			Vec3 x;
			for (int i = 0; i < 3; i++)
				if (!finite_number(w[1 + i], x[i]))
					return at(path, line, "a vertex coordinate " + quoted(w[1 + i]) + " is not a finite number");
			if (vertices.size() == max_vertices)
				return at(path, line, "more than " + std::to_string(max_vertices) + " vertices: tcs reads no more");
			vertices.push_back(x);
		} else if (w[0] == "f") {
			if (w.size() < 4)
				return at(path, line, "a face needs at least 3 corners, not " + std::to_string(w.size() - 1));
			face.clear();
			for (size_t i = 1; i < w.size(); i++) {
				auto c = corner(path, line, w[i], vertices.size());
				if (!c.ok())
					return c.error();
				face.push_back(*c);
			}
			if (soup.size() / 3 + face.size() - 2 > kMaxMeshTriangles)
				return at(path, line, "more than " + std::to_string(kMaxMeshTriangles) +
							      " triangles: tcs reads no more (simplify the collision mesh)");
			for (size_t i = 1; i + 1 < face.size(); i++)
				soup.insert(soup.end(), { vertices[face[0]], vertices[face[i]], vertices[face[i + 1]] });
		}
		// Anything else (vn, vt, o, g, s, usemtl, mtllib, l, comments)
		// says nothing about the collision shape.
	}
	return soup;
}

} // namespace tcs::sim::robot
