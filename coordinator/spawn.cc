// spawn_stopped(): fork, prepare the child, stop it before exec.
#include "spawn.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#include "tcs/protocol.h"

extern char **environ;

namespace tcs {

namespace {

bool is_tcs_variable(const char *kv)
{
	return std::strncmp(kv, "TCS_CHANNEL_FD=", 15) == 0 || std::strncmp(kv, "TCS_PAGE_FD=", 12) == 0 ||
	       std::strncmp(kv, "TCS_CONTROLLER_PID=", 19) == 0 || std::strncmp(kv, "LD_PRELOAD=", 11) == 0;
}

// Where the runtime's fds go in the controller: high, out of the program's
// way, but below its descriptor limit.
int runtime_fd_floor()
{
	struct rlimit rl;
	int floor = TCS_RUNTIME_FD_FLOOR;
	if (getrlimit(RLIMIT_NOFILE, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY && rl.rlim_cur < (rlim_t)floor + 2)
		floor = (int)rl.rlim_cur - 2;
	return floor < 3 ? 3 : floor;
}

// Writes decimal n at the end of buf (which has room) in the child, where
// snprintf is not async-signal-safe.
void put_decimal(char *at, long n)
{
	char tmp[24];
	int len = 0;
	do
		tmp[len++] = (char)('0' + n % 10);
	while ((n /= 10) > 0);
	while (len > 0)
		*at++ = tmp[--len];
	*at = '\0';
}

[[noreturn]] void child_fail(const char *what, const char *path)
{
	char msg[512];
	int n = snprintf(msg, sizeof msg, "tcs-run: %s %s: %s\n", what, path, strerror(errno));
	if (n > 0)
		(void)!write(2, msg, (size_t)n);
	_exit(127);
}

} // namespace

Result<Spawned> spawn_stopped(const SpawnRequest &req)
{
	int floor = runtime_fd_floor();
	std::vector<std::string> env_strings;
	// The environment the program is to have: the caller's, or ours.
	std::vector<const char *> base;
	if (req.env)
		for (const auto &kv : *req.env)
			base.push_back(kv.c_str());
	else
		for (char **e = environ; e && *e; e++)
			base.push_back(*e);
	std::string preload = "LD_PRELOAD=" + req.preload;
	for (const char *kv : base)
		if (std::strncmp(kv, "LD_PRELOAD=", 11) == 0 && kv[11])
			preload += std::string(":") + (kv + 11);
	env_strings.push_back(preload);
	env_strings.push_back(std::string(TCS_ENV_CHANNEL_FD) + "=" + std::to_string(floor));
	env_strings.push_back(std::string(TCS_ENV_PAGE_FD) + "=" + std::to_string(floor + 1));
	std::string pid_var = std::string(TCS_ENV_CONTROLLER_PID) + "=";
	size_t pid_at = pid_var.size();
	pid_var.resize(pid_at + 24, '\0');
	std::vector<char *> envp;
	for (const char *kv : base)
		if (!is_tcs_variable(kv))
			envp.push_back(const_cast<char *>(kv));
	for (auto &s : env_strings)
		envp.push_back(s.data());
	envp.push_back(pid_var.data());
	envp.push_back(nullptr);
	std::vector<char *> argv;
	std::vector<std::string> argv_copy = req.argv;
	for (auto &a : argv_copy)
		argv.push_back(a.data());
	argv.push_back(nullptr);

	pid_t parent = getpid();
	pid_t pid = fork();
	if (pid < 0)
		return errno_error("fork");
	if (pid == 0) {
		// The child: only async-signal-safe calls from here to exec.
		prctl(PR_SET_PDEATHSIG, SIGKILL);
		if (getppid() != parent)
			_exit(127);
		sigset_t none;
		sigemptyset(&none);
		sigprocmask(SIG_SETMASK, &none, nullptr);
		apply_controller_realtime(req.realtime);
		if (dup2(req.channel_fd, floor) < 0 || dup2(req.page_fd, floor + 1) < 0)
			child_fail("cannot set up the channel for", req.path.c_str());
		for (int i = 0; i < 3; i++)
			if (req.stdio[i] >= 0 && req.stdio[i] != i && dup2(req.stdio[i], i) < 0)
				child_fail("cannot set up the standard streams for", req.path.c_str());
		if (!req.cwd.empty() && chdir(req.cwd.c_str()) < 0)
			child_fail("cannot enter the working directory of", req.path.c_str());
		// Someone else's: a group of its own, out of reach of the daemon's
		// terminal (its caller's Ctrl-C comes through tcs-run).
		if (req.env)
			setpgid(0, 0);
		put_decimal(pid_var.data() + pid_at, (long)getpid());
		raise(SIGSTOP);
		execve(req.path.c_str(), argv.data(), envp.data());
		child_fail("cannot execute", req.path.c_str());
	}

	Spawned out;
	out.pid = pid;
	out.pidfd.reset((int)syscall(SYS_pidfd_open, pid, 0));
	if (!out.pidfd) {
		Error e = errno_error("pidfd_open");
		kill(pid, SIGKILL);
		waitpid(pid, nullptr, 0);
		return e;
	}
	siginfo_t si = {};
	if (waitid(P_PID, pid, &si, WSTOPPED | WEXITED) < 0 || si.si_code != CLD_STOPPED) {
		Error e = errno_error("controller did not start");
		kill(pid, SIGKILL);
		waitpid(pid, nullptr, 0);
		return e;
	}
	return out;
}

} // namespace tcs
