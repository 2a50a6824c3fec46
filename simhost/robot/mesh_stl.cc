// read_stl: a binary STL (an 80-byte header, a 32-bit triangle count, 50
// bytes a triangle) or an ASCII one (solid / facet / vertex ...). A file
// is binary when its size is exactly what its count says, whatever its
// header (binary headers often begin with "solid" too), else ASCII when
// it begins with "solid".
#include "mesh_stl.h"

#include <cstdint>
#include <cstring>

#include "mesh_load.h"
#include "robot_xml.h"

namespace tcs::sim::robot {

namespace {

constexpr size_t header_bytes = 84, triangle_bytes = 50;

uint32_t u32_le(const unsigned char *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

float f32_le(const unsigned char *p)
{
	uint32_t u = u32_le(p);
	float f;
	std::memcpy(&f, &u, sizeof f);
	return f;
}

Result<Soup> read_binary(const std::string &path, std::string_view bytes, uint64_t count)
{
	uint64_t want = header_bytes + triangle_bytes * count;
	if (want > bytes.size())
		return at(path, 0, "a binary STL claiming " + std::to_string(count) + " triangles (" + std::to_string(want) +
					   " bytes), but the file has " + std::to_string(bytes.size()) +
					   " bytes: truncated, or not an STL");
	if (count > kMaxMeshTriangles)
		return at(path, 0, std::to_string(count) + " triangles: tcs reads at most " +
					   std::to_string(kMaxMeshTriangles) + " (simplify the collision mesh)");
	const auto *p = reinterpret_cast<const unsigned char *>(bytes.data()) + header_bytes;
	Soup soup;
	soup.reserve(3 * count);
	for (uint64_t t = 0; t < count; t++, p += triangle_bytes)
		for (int c = 0; c < 3; c++) {
			const unsigned char *v = p + 12 + 12 * c; // after the normal
			Vec3 x{ f32_le(v), f32_le(v + 4), f32_le(v + 8) };
			if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
				return at(path, 0, "triangle " + std::to_string(t + 1) + " has a vertex that is not finite");
			soup.push_back(x);
		}
	return soup;
}

bool is(std::string_view w, const char *keyword)
{
	size_t n = std::strlen(keyword);
	if (w.size() != n)
		return false;
	for (size_t i = 0; i < n; i++)
		if ((w[i] | 0x20) != keyword[i]) // ASCII case folded: some writers shout
			return false;
	return true;
}

Result<Soup> read_ascii(const std::string &path, std::string_view bytes)
{
	Soup soup;
	Words text(bytes);
	std::vector<std::string_view> w;
	bool in_facet = false;
	int corners = 0, facet_line = 0;
	size_t triangles = 0;
	while (text.next_line(w)) {
		if (w.empty() || is(w[0], "solid") || is(w[0], "endsolid") || is(w[0], "outer") || is(w[0], "endloop"))
			continue;
		int line = text.line();
		if (is(w[0], "facet")) {
			if (in_facet)
				return at(path, line, "a facet inside the facet of line " + std::to_string(facet_line));
			in_facet = true;
			corners = 0;
			facet_line = line;
		} else if (is(w[0], "vertex")) {
			if (!in_facet)
				return at(path, line, "a vertex outside a facet");
			if (w.size() != 4)
				return at(path, line, "a vertex needs 3 numbers, not " + std::to_string(w.size() - 1));
			Vec3 x;
			for (int i = 0; i < 3; i++)
				if (!finite_number(w[1 + i], x[i]))
					return at(path, line, "a vertex coordinate " + quoted(w[1 + i]) + " is not a finite number");
			if (++corners > 3)
				return at(path, line, "a facet with more than 3 vertices");
			soup.push_back(x);
		} else if (is(w[0], "endfacet")) {
			if (!in_facet || corners != 3)
				return at(path, line, in_facet ? "a facet with " + std::to_string(corners) + " vertices, not 3"
							       : std::string("endfacet without facet"));
			in_facet = false;
			if (++triangles > kMaxMeshTriangles)
				return at(path, line, "more than " + std::to_string(kMaxMeshTriangles) +
							      " triangles: tcs reads no more (simplify the collision mesh)");
		} else {
			return at(path, line, "neither a binary STL nor an ASCII one: " + quoted(w[0]) +
						      " is not an STL keyword");
		}
	}
	if (in_facet)
		return at(path, text.line(), "the file ends inside the facet of line " + std::to_string(facet_line) +
						     " (truncated?)");
	return soup;
}

bool begins_with_solid(std::string_view bytes)
{
	size_t i = bytes.find_first_not_of(" \t\r\n");
	return i != std::string_view::npos && bytes.substr(i, 5) == "solid";
}

} // namespace

Result<Soup> read_stl(const std::string &path, std::string_view bytes)
{
	if (bytes.size() >= header_bytes) {
		uint64_t count = u32_le(reinterpret_cast<const unsigned char *>(bytes.data()) + 80);
		if (header_bytes + triangle_bytes * count == bytes.size() || !begins_with_solid(bytes))
			return read_binary(path, bytes, count);
	}
	if (begins_with_solid(bytes))
		return read_ascii(path, bytes);
	return at(path, 0, "not an STL: too short for a binary one (" + std::to_string(bytes.size()) +
				   " bytes) and not an ASCII one (no 'solid')");
}

} // namespace tcs::sim::robot
