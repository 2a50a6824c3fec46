// coordinatord's command line: its options, their checks and its help.
#pragma once

#include <string>

#include "coordinator.h"
#include "error.h"

namespace tcs {

struct DaemonOptions {
	// The run's options (run_options.h); main completes it into the
	// coordinator's configuration.
	CoordinatorConfig cfg;
	std::string world_file, socket_path;
	int dds_domain = -1;
	bool quiet = false, agent = false, mode_given = false;
	std::string agent_name;
	// -h or -V: print that in place of a run.
	bool help = false, version = false;
};

// Reads the command line, stopping at an -h or -V; every error is a usage error.
Result<DaemonOptions> parse_options(int argc, char **argv);
// Prints the help or the version, as -h or -V asked.
void print_help_or_version(const DaemonOptions &o);

} // namespace tcs
