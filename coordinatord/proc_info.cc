// proc_info: /proc/PID/stat read once per question. Its second field (the
// command) may hold spaces and parentheses, so fields count from the last ')'.
#include "proc_info.h"

#include <dirent.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace tcs {

namespace {

// The fields of a stat file from the third (state) on; empty if unreadable.
std::vector<std::string> stat_fields(const std::string &path)
{
	std::ifstream f(path);
	std::string stat((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
	std::vector<std::string> fields;
	size_t close = stat.rfind(')');
	if (close == std::string::npos)
		return fields;
	std::istringstream in(stat.substr(close + 1));
	for (std::string field; in >> field;)
		fields.push_back(field);
	return fields;
}

std::string stat_path(pid_t pid)
{
	return "/proc/" + std::to_string(pid) + "/stat";
}

} // namespace

pid_t proc_parent(pid_t pid)
{
	auto f = stat_fields(stat_path(pid));
	return f.size() > 1 ? (pid_t)atoi(f[1].c_str()) : 0; // field 4
}

std::string proc_name(pid_t pid, const std::string &fallback)
{
	std::ifstream f("/proc/" + std::to_string(pid) + "/comm");
	std::string name;
	return std::getline(f, name) && !name.empty() ? name : fallback;
}

int proc_exit_status(pid_t pid)
{
	auto f = stat_fields(stat_path(pid));
	return f.size() > 49 ? atoi(f[49].c_str()) : 0; // field 52
}

bool proc_all_threads_asleep(pid_t pid)
{
	std::string dir = "/proc/" + std::to_string(pid) + "/task";
	DIR *d = opendir(dir.c_str());
	if (!d)
		return true; // gone
	bool asleep = true;
	while (struct dirent *e = readdir(d)) {
		if (e->d_name[0] == '.')
			continue;
		auto f = stat_fields(dir + "/" + e->d_name + "/stat");
		if (!f.empty() && f[0] != "S" && f[0] != "D") {
			asleep = false;
			break;
		}
	}
	closedir(d);
	return asleep;
}

} // namespace tcs
