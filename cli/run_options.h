// The options of a run that tcs-run and coordinatord both take (--mode,
// --epoch, --no-slack, --spin-cost, --seed): one parser, one help text.
#pragma once

#include <getopt.h>

#include <string>

#include "coordinator.h"
#include "error.h"

// Their lines of --help, the same in both.
#define TCS_RUN_OPTIONS_HELP                                                              \
	"  -m, --mode cpu|lockstep\n"                                                      \
	"                         cpu (default): computation costs virtual time;\n"        \
	"                         lockstep: computation is free (the status quo)\n"        \
	"      --epoch TIME       virtual wall-clock start: RFC 3339 or seconds since 1970\n" \
	"      --no-slack         waits end exactly at their deadlines (default: their\n"  \
	"                         thread's timer slack later, 50 us unless it set one)\n"  \
	"      --spin-cost C[,R]  lockstep: the virtual time a spinning clock read (C)\n"  \
	"                         and empty read or poll (R) take (default: measured;\n"   \
	"                         25ns,500ns with --epoch; 0: spins take none)\n"          \
	"      --seed N           the randomness programs draw from the system\n"          \
	"                         (getrandom, /dev/urandom) a stream fixed by N\n"

namespace tcs {

// The long name of getopt_long's result opt if it is one of them, else "".
std::string run_option_of(const struct option *longopts, int opt);
// Sets option name's part of cfg from its argument (none for --no-slack);
// the error names the option ("--seed: 'x' is not a whole number ...").
Status set_run_option(const std::string &name, const std::string &arg, CoordinatorConfig &cfg);

} // namespace tcs
