// tcs-run --connect: the controller runs under an already running
// coordinatord, in its shared world. tcs-run hands over the program, its
// arguments, environment, working directory and stdin/stdout/stderr, passes
// on the signals it gets (Ctrl-C), and ends with the controller's status.
#pragma once

#include <string>
#include <vector>

#include "error.h"

namespace tcs {

struct ConnectRequest {
	std::string socket;
	std::string path; // resolved as execvp would
	std::vector<std::string> argv;
	double cpu_scale = 0; // 0: the daemon's choice
	bool quiet = false;
};

// tcs-run's exit status once the controller has ended.
Result<int> run_connected(const ConnectRequest &req);

} // namespace tcs
