// proc_info: /proc/PID/stat read once per question. Its second field (the
// command) may hold spaces and parentheses, so fields count from the last ')'.
#include "proc_info.h"

#include <dirent.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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

namespace {

// A thread's state letter (stat field 3), read without allocating: this is
// on the path of every wait of a multi-threaded controller. 0 if gone.
char task_state(int dir_fd, const char *tid)
{
	char path[NAME_MAX + 8]; // (a directory entry's name and "/stat")
	snprintf(path, sizeof path, "%s/stat", tid);
	int fd = openat(dir_fd, path, O_RDONLY | O_CLOEXEC);
	if (fd < 0)
		return 0;
	char buf[512];
	ssize_t n = read(fd, buf, sizeof buf - 1);
	close(fd);
	if (n <= 0)
		return 0;
	buf[n] = '\0';
	const char *close_paren = strrchr(buf, ')');
	return close_paren && close_paren[1] == ' ' ? close_paren[2] : 0;
}

} // namespace

ThreadCensus proc_threads(pid_t pid, std::span<const pid_t> except)
{
	ThreadCensus census;
	char dir[40];
	snprintf(dir, sizeof dir, "/proc/%d/task", (int)pid);
	DIR *d = opendir(dir);
	if (!d)
		return census;
	while (struct dirent *e = readdir(d)) {
		if (e->d_name[0] == '.')
			continue;
		char state = task_state(dirfd(d), e->d_name);
		if (state == 0 || state == 'Z' || state == 'X')
			continue;
		census.threads++;
		pid_t tid = (pid_t)atoi(e->d_name);
		if (state == 'R' && std::find(except.begin(), except.end(), tid) == except.end())
			census.runnable++;
	}
	closedir(d);
	return census;
}

std::vector<ThreadState> proc_thread_states(pid_t pid)
{
	std::vector<ThreadState> out;
	char dir[40];
	snprintf(dir, sizeof dir, "/proc/%d/task", (int)pid);
	DIR *d = opendir(dir);
	if (!d)
		return out;
	while (struct dirent *e = readdir(d)) {
		if (e->d_name[0] == '.')
			continue;
		char state = task_state(dirfd(d), e->d_name);
		if (state != 0 && state != 'Z' && state != 'X')
			out.push_back({ (pid_t)atoi(e->d_name), state });
	}
	closedir(d);
	return out;
}

bool proc_all_threads_stopped(pid_t pid)
{
	char dir[40];
	snprintf(dir, sizeof dir, "/proc/%d/task", (int)pid);
	DIR *d = opendir(dir);
	if (!d)
		return true;
	bool stopped = true;
	while (struct dirent *e = readdir(d)) {
		if (e->d_name[0] == '.')
			continue;
		char state = task_state(dirfd(d), e->d_name);
		if (state != 0 && state != 'T' && state != 't' && state != 'Z' && state != 'X') {
			stopped = false;
			break;
		}
	}
	closedir(d);
	return stopped;
}

std::vector<pid_t> proc_children(pid_t pid)
{
	std::vector<pid_t> out;
	char dir[40];
	snprintf(dir, sizeof dir, "/proc/%d/task", (int)pid);
	DIR *d = opendir(dir);
	if (!d)
		return out;
	while (struct dirent *e = readdir(d)) {
		if (e->d_name[0] == '.')
			continue;
		std::ifstream f(std::string(dir) + "/" + e->d_name + "/children");
		for (pid_t child; f >> child;)
			out.push_back(child);
	}
	closedir(d);
	return out;
}

bool proc_maps_library(pid_t pid, const char *name)
{
	std::ifstream f("/proc/" + std::to_string(pid) + "/maps");
	std::string line;
	bool any = false;
	while (std::getline(f, line)) {
		if (line.find(name) != std::string::npos)
			return true;
		any = true;
	}
	return !any; // unreadable, or a process on its way out: no verdict

}

bool proc_has_thread(pid_t pid, pid_t tid)
{
	char path[64];
	snprintf(path, sizeof path, "/proc/%d/task/%d", (int)pid, (int)tid);
	return access(path, F_OK) == 0;
}

} // namespace tcs
