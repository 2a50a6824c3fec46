// What the mesh readers (mesh_stl.h, mesh_obj.h) share: the triangle
// soup they give load_mesh, and for the text formats, splitting into lines
// and words and reading a number.
#pragma once

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "description.h"
#include "error.h"

namespace tcs::sim::robot {

// Three corners a triangle, as the file wound them, before scaling and
// indexing (load_mesh).
using Soup = std::vector<Vec3>;

// A text file's lines, each split into words at blanks.
class Words {
public:
	explicit Words(std::string_view text) : rest_(text) {}
	// The next line's words (empty for a blank line); false at the end.
	bool next_line(std::vector<std::string_view> &words)
	{
		if (rest_.empty())
			return false;
		size_t nl = rest_.find('\n');
		std::string_view line = rest_.substr(0, nl);
		rest_.remove_prefix(nl == std::string_view::npos ? rest_.size() : nl + 1);
		line_++;
		words.clear();
		size_t i = 0;
		while (i < line.size()) {
			while (i < line.size() && blank(line[i]))
				i++;
			size_t b = i;
			while (i < line.size() && !blank(line[i]))
				i++;
			if (i > b)
				words.push_back(line.substr(b, i - b));
		}
		return true;
	}
	int line() const { return line_; }

private:
	static bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
	std::string_view rest_;
	int line_ = 0;
};

// A whole word as a finite number (a leading '+' allowed, as C's strtod
// reads it; locale-independent, unlike strtod).
inline bool finite_number(std::string_view w, double &out)
{
	if (!w.empty() && w[0] == '+') {
		w.remove_prefix(1);
		if (!w.empty() && w[0] == '-')
			return false;
	}
	auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), out);
	return ec == std::errc() && end == w.data() + w.size() && std::isfinite(out);
}

// A word of the file quoted for a message: a binary file's bytes could
// be anything.
inline std::string quoted(std::string_view w)
{
	std::string s = "'";
	for (size_t i = 0; i < w.size() && i < 32; i++)
		s += w[i] >= 0x20 && w[i] < 0x7f ? w[i] : '?';
	return s + (w.size() > 32 ? "...'" : "'");
}

} // namespace tcs::sim::robot
