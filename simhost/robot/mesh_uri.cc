// resolve_mesh_uri: the candidates of each scheme tried in order, each
// remembered for the message when none is a file.
#include "mesh_uri.h"

#include <cstdlib>
#include <filesystem>
#include <vector>

namespace tcs::sim::robot {

namespace {

namespace fs = std::filesystem;

struct Search {
	std::vector<std::string> looked; // for the message
	std::string found;

	bool try_path(const fs::path &p)
	{
		std::error_code ec;
		if (fs::is_regular_file(p, ec)) {
			found = p.lexically_normal().string();
			return true;
		}
		looked.push_back(p.lexically_normal().string());
		return false;
	}
};

bool starts_with(const std::string &s, const char *prefix)
{
	return s.rfind(prefix, 0) == 0;
}

std::vector<std::string> env_folders(const char *var)
{
	std::vector<std::string> out;
	const char *v = std::getenv(var);
	std::string s = v ? v : "";
	size_t b = 0;
	while (b <= s.size()) {
		size_t e = s.find(':', b);
		if (e == std::string::npos)
			e = s.size();
		std::string d = s.substr(b, e - b);
		while (d.size() > 1 && d.back() == '/') // "pkg/" is named pkg too
			d.pop_back();
		if (!d.empty())
			out.push_back(d);
		b = e + 1;
	}
	return out;
}

// The robot file's folder, absolute, for ancestors and relative paths.
fs::path folder_of(const std::string &robot_file)
{
	std::error_code ec;
	fs::path abs = fs::absolute(robot_file, ec);
	return (ec ? fs::path(robot_file) : abs).lexically_normal().parent_path();
}

// A folder named name above the robot file: its rest.
void try_ancestors(Search &s, const std::string &robot_file, const std::string &name, const std::string &rest)
{
	bool any = false;
	for (fs::path p = folder_of(robot_file); !p.empty(); p = p.parent_path()) {
		if (p.filename() == name) {
			any = true;
			if (s.try_path(p / rest))
				return;
		}
		if (p == p.parent_path())
			break;
	}
	if (!any)
		s.looked.push_back("no folder '" + name + "' above " + folder_of(robot_file).string());
}

// "PKG/REST" split; false when either is empty.
bool split(const std::string &s, std::string &name, std::string &rest)
{
	size_t slash = s.find('/');
	if (slash == std::string::npos || slash == 0 || slash + 1 == s.size())
		return false;
	name = s.substr(0, slash);
	rest = s.substr(slash + 1);
	return true;
}

void try_env(Search &s, const char *var, const std::string &name, const std::string &rest, const char *under = "")
{
	std::vector<std::string> dirs = env_folders(var);
	if (dirs.empty())
		s.looked.push_back(std::string("$") + var + " (unset)");
	for (const std::string &d : dirs) {
		if (s.try_path(fs::path(d) / under / name / rest))
			return;
		if (!*under && fs::path(d).lexically_normal().filename() == name && s.try_path(fs::path(d) / rest))
			return;
	}
}

std::string not_found(const std::string &uri, const Search &s)
{
	std::string m = "mesh '" + uri + "' not found (looked in: ";
	for (size_t i = 0; i < s.looked.size(); i++)
		m += (i ? ", " : "") + s.looked[i];
	return m + ")";
}

} // namespace

Result<std::string> resolve_mesh_uri(const std::string &uri, const std::string &robot_file)
{
	Search s;
	std::string name, rest;
	if (starts_with(uri, "package://") || starts_with(uri, "model://")) {
		bool package = starts_with(uri, "package://");
		if (!split(uri.substr(package ? 10 : 8), name, rest))
			return Error{ "mesh '" + uri + "': a " + (package ? "package" : "model") + ":// URI names " +
				      (package ? "a package" : "a model") + " and a file in it" };
		if (package) {
			try_env(s, "ROS_PACKAGE_PATH", name, rest);
			if (s.found.empty())
				try_env(s, "AMENT_PREFIX_PATH", name, rest, "share");
		} else {
			for (const char *var : { "GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "SDF_PATH",
						 "GAZEBO_MODEL_PATH" })
				if (s.found.empty())
					try_env(s, var, name, rest);
		}
		if (s.found.empty())
			try_ancestors(s, robot_file, name, rest);
	} else {
		std::string path = starts_with(uri, "file://") ? uri.substr(7) : uri;
		if (path.find("://") != std::string::npos || path.empty())
			return Error{ "mesh '" + uri +
				      "': tcs finds meshes by relative path, file://, package:// and model:// URIs only" };
		fs::path p(path);
		s.try_path(p.is_absolute() ? p : folder_of(robot_file) / p);
	}
	if (s.found.empty())
		return Error{ not_found(uri, s) };
	return s.found;
}

} // namespace tcs::sim::robot
