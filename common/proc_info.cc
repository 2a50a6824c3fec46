// proc_info: /proc/PID/stat read once per question. Its second field (the
// command) may hold spaces and parentheses, so fields count from the last ')'.
// Every file is read with read(), never a stream: a process that ends while
// its file is read fails the read with ESRCH, which a std::ifstream turns
// into an exception (it ended tcs-run once, seen).
#include "proc_info.h"

#include <dirent.h>
#include <fcntl.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

#include "read_file.h"

namespace tcs {

namespace {

// What a /proc file says now; empty if it cannot be read (the process has
// gone, or is going).
std::string proc_text(const std::string &path)
{
	auto text = read_file(path, 64 << 20);
	return text ? std::move(*text) : std::string();
}

// The fields of a stat file from the third (state) on; empty if unreadable.
std::vector<std::string> stat_fields(const std::string &path)
{
	std::string stat = proc_text(path);
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
	std::string name = proc_text("/proc/" + std::to_string(pid) + "/comm");
	name = name.substr(0, name.find('\n'));
	return !name.empty() ? name : fallback;
}

int proc_exit_status(pid_t pid)
{
	auto f = stat_fields(stat_path(pid));
	return f.size() > 49 ? atoi(f[49].c_str()) : 0; // field 52
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

// Calls f(task directory fd, thread id as a string) for each thread of
// pid while f returns true; false if pid is gone.
template <class F> bool for_each_task(pid_t pid, F f)
{
	char dir[40];
	snprintf(dir, sizeof dir, "/proc/%d/task", (int)pid);
	DIR *d = opendir(dir);
	if (!d)
		return false;
	while (struct dirent *e = readdir(d))
		if (e->d_name[0] != '.' && !f(dirfd(d), e->d_name))
			break;
	closedir(d);
	return true;
}

bool live(char state)
{
	return state != 0 && state != 'Z' && state != 'X';
}

} // namespace

bool proc_all_threads_asleep(pid_t pid)
{
	bool asleep = true;
	for_each_task(pid, [&](int dir, const char *tid) {
		char state = task_state(dir, tid);
		asleep = state == 0 || state == 'S' || state == 'D';
		return asleep;
	});
	return asleep; // (gone: asleep)
}

int proc_thread_count(pid_t pid)
{
	int n = 0;
	for_each_task(pid, [&](int dir, const char *tid) {
		n += live(task_state(dir, tid));
		return true;
	});
	return n;
}

std::vector<ThreadState> proc_thread_states(pid_t pid)
{
	std::vector<ThreadState> out;
	for_each_task(pid, [&](int dir, const char *tid) {
		char state = task_state(dir, tid);
		if (live(state))
			out.push_back({ (pid_t)atoi(tid), state });
		return true;
	});
	return out;
}

bool proc_all_threads_stopped(pid_t pid)
{
	bool stopped = true;
	for_each_task(pid, [&](int dir, const char *tid) {
		char state = task_state(dir, tid);
		stopped = !live(state) || state == 'T' || state == 't';
		return stopped;
	});
	return stopped;
}

namespace {

// Whether sig is in the hexadecimal signal mask after "key:\t" in status.
bool in_mask(const std::string &status, const char *key, int sig)
{
	size_t at = status.find(std::string("\n") + key + ":");
	if (at == std::string::npos)
		return false;
	const unsigned long long mask = strtoull(status.c_str() + at + strlen(key) + 2, nullptr, 16);
	return sig >= 1 && sig <= 64 && ((mask >> (sig - 1)) & 1);
}

} // namespace

bool proc_signal_kills(pid_t pid, int sig)
{
	const std::string status = proc_text("/proc/" + std::to_string(pid) + "/status");
	if (status.empty() || in_mask(status, "SigCgt", sig) || in_mask(status, "SigIgn", sig))
		return false;
	bool unblocked = false;
	for_each_task(pid, [&](int dir, const char *tid) {
		char path[NAME_MAX + 8];
		snprintf(path, sizeof path, "%s/status", tid);
		int fd = openat(dir, path, O_RDONLY | O_CLOEXEC);
		if (fd < 0)
			return true;
		std::string text(4096, '\0');
		ssize_t n = read(fd, text.data(), text.size());
		close(fd);
		if (n <= 0)
			return true;
		text.resize((size_t)n);
		unblocked = text.find("\nState:\tZ") == std::string::npos && !in_mask(text, "SigBlk", sig);
		return !unblocked;
	});
	return unblocked;
}

std::vector<pid_t> proc_children(pid_t pid)
{
	std::vector<pid_t> out;
	std::string dir = "/proc/" + std::to_string(pid) + "/task/";
	for_each_task(pid, [&](int, const char *tid) {
		std::istringstream f(proc_text(dir + tid + "/children"));
		for (pid_t child; f >> child;)
			out.push_back(child);
		return true;
	});
	return out;
}

namespace {
// What pid's maps say: whether a file whose name contains name is mapped,
// and whether a dynamic loader and anything at all are.
struct MapsSeen {
	bool found = false, loader = false, any = false;
};
MapsSeen scan_maps(pid_t pid, const char *name)
{
	MapsSeen seen;
	std::istringstream f(proc_text("/proc/" + std::to_string(pid) + "/maps"));
	std::string line;
	while (!seen.found && std::getline(f, line)) {
		seen.any = true;
		seen.found = line.find(name) != std::string::npos;
		seen.loader = seen.loader || line.find("/ld-") != std::string::npos;
	}
	return seen;
}
} // namespace

bool proc_maps_library(pid_t pid, const char *name)
{
	MapsSeen seen = scan_maps(pid, name);
	return seen.found || !seen.any; // unreadable, or a process on its way out: no verdict
}

bool proc_has_thread(pid_t pid, pid_t tid)
{
	char path[64];
	snprintf(path, sizeof path, "/proc/%d/task/%d", (int)pid, (int)tid);
	return access(path, F_OK) == 0;
}

bool proc_task_exists(pid_t tid)
{
	char path[32];
	snprintf(path, sizeof path, "/proc/%d", (int)tid);
	return access(path, F_OK) == 0;
}

WillLoad proc_will_load(pid_t pid, const char *name)
{
	// The environment is laid out last, the loader mapped by then: read
	// first, it says whether what the maps say next is final.
	std::istringstream env(proc_text("/proc/" + std::to_string(pid) + "/environ"));
	std::string var;
	bool laid_out = false, preload = false;
	while (std::getline(env, var, '\0')) {
		laid_out = true;
		if (var.rfind("LD_PRELOAD=", 0) == 0)
			preload = var.find(name) != std::string::npos;
	}
	MapsSeen maps = scan_maps(pid, name);
	if (maps.found)
		return WillLoad::Yes;
	if (!laid_out)
		return WillLoad::Unknown;
	return maps.loader && preload ? WillLoad::Yes : WillLoad::No;
}

} // namespace tcs
