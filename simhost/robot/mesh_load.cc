// load_mesh: the format from the file's extension, its reader's triangle
// soup (mesh_stl.h, mesh_obj.h), scaled, then indexed: equal corners become one
// vertex, so that ODE's trimesh sees shared edges.
#include "mesh_load.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "mesh_obj.h"
#include "mesh_stl.h"
#include "read_file.h"
#include "robot_xml.h"

namespace tcs::sim::robot {

namespace {

std::string extension(const std::string &path)
{
	size_t slash = path.find_last_of('/');
	size_t dot = path.find_last_of('.');
	if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
		return "";
	std::string e = path.substr(dot + 1);
	for (char &c : e)
		c = (char)std::tolower((unsigned char)c);
	return e;
}

// The formats robot files commonly name that tcs does not read.
const char *format_name(const std::string &ext)
{
	if (ext == "dae")
		return "Collada (.dae)";
	if (ext == "glb" || ext == "gltf")
		return "glTF (.glb, .gltf)";
	if (ext == "fbx")
		return "FBX (.fbx)";
	if (ext == "ply")
		return "PLY (.ply)";
	if (ext == "3ds")
		return "3DS (.3ds)";
	return nullptr;
}

// A vertex's bits as a key: -0 made +0 first, so that the two zeros merge
// as they compare equal.
struct Key {
	uint64_t b[3];
	bool operator==(const Key &o) const { return std::memcmp(b, o.b, sizeof b) == 0; }
};

struct KeyHash {
	size_t operator()(const Key &k) const
	{
		uint64_t h = 1469598103934665603ull;
		for (uint64_t x : k.b)
			h = (h ^ x) * 1099511628211ull;
		return (size_t)(h ^ (h >> 29));
	}
};

Key key(const Vec3 &v)
{
	Key k;
	for (int i = 0; i < 3; i++) {
		double d = v[i] + 0.0;
		std::memcpy(&k.b[i], &d, sizeof d);
	}
	return k;
}

Mesh indexed(const Soup &soup, bool mirrored)
{
	Mesh m;
	std::unordered_map<Key, unsigned, KeyHash> index;
	index.reserve(soup.size());
	m.indices.reserve(soup.size());
	for (size_t t = 0; t + 2 < soup.size(); t += 3) {
		unsigned tri[3];
		for (int c = 0; c < 3; c++) {
			auto [it, added] = index.emplace(key(soup[t + c]), (unsigned)m.vertices.size());
			if (added)
				m.vertices.push_back(soup[t + c]);
			tri[c] = it->second;
		}
		if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
			continue; // no area, no side: nothing to collide with
		if (mirrored)
			std::swap(tri[1], tri[2]);
		m.indices.insert(m.indices.end(), { tri[0], tri[1], tri[2] });
	}
	// Vertices only dropped triangles used stay unused: harmless to ODE,
	// and rare enough not to compact.
	return m;
}

} // namespace

Result<Mesh> load_mesh(const std::string &path, Vec3 scale)
{
	for (double s : scale)
		if (!std::isfinite(s) || s == 0)
			return at(path, 0, "the mesh's scale must be finite and non-zero on each axis");
	std::string ext = extension(path);
	bool stl = ext == "stl", obj = ext == "obj";
	if (!stl && !obj) {
		const char *name = format_name(ext);
		return at(path, 0, std::string("tcs reads STL and OBJ meshes, not ") +
					   (name ? name : ext.empty() ? "files without an extension" : "." + ext + " files") +
					   ": convert it to STL");
	}
	auto bytes = read_file(path, kMaxMeshFileBytes);
	if (!bytes.ok())
		return bytes.error();
	auto soup = stl ? read_stl(path, *bytes) : read_obj(path, *bytes);
	if (!soup.ok())
		return soup.error();
	for (Vec3 &v : *soup)
		for (int i = 0; i < 3; i++)
			v[i] *= scale[i];
	bool mirrored = ((scale[0] < 0) != (scale[1] < 0)) != (scale[2] < 0);
	Mesh m = indexed(*soup, mirrored);
	if (m.indices.empty())
		return at(path, 0, "the mesh has no triangles (none with an area)");
	for (const Vec3 &v : m.vertices)
		for (double x : v)
			if (!std::isfinite(x)) // a huge coordinate times the scale
				return at(path, 0, "a vertex is not finite once scaled");
	return m;
}

} // namespace tcs::sim::robot
