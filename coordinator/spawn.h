// Starting a controller: a child that dies with the coordinator, runs one
// priority below it on its core, finds its channel and clock page at fixed
// high fds, loads libtcs_preload, and stops itself just before exec so that
// the coordinator schedules it from its very first instruction.
#pragma once

#include <sys/types.h>

#include <array>
#include <string>
#include <vector>

#include "error.h"
#include "realtime.h"
#include "unique_fd.h"

namespace tcs {

struct SpawnRequest {
	std::string path;              // the executable, resolved
	std::vector<std::string> argv; // argv[0] as the user gave it
	std::string preload;           // absolute path of libtcs_preload.so
	int channel_fd = -1;           // the controller's end of the channel
	int page_fd = -1;              // the clock page memfd
	RealtimePlan realtime;
	// Someone else's: their environment (else the coordinator's), working
	// directory (else ours) and stdin/stdout/stderr (-1: ours).
	const std::vector<std::string> *env = nullptr;
	std::string cwd;
	std::array<int, 3> stdio = { -1, -1, -1 };
};

struct Spawned {
	pid_t pid = -1;
	UniqueFd pidfd;
};

// Forks the controller; on success it is stopped (SIGSTOP) before exec.
Result<Spawned> spawn_stopped(const SpawnRequest &req);

} // namespace tcs
