// coordinatord's command line, read into DaemonOptions.
#include "daemon_options.h"

#include <getopt.h>

#include <cstdio>
#include <cstdlib>

#include "cli_errors.h"
#include "run_options.h"

namespace tcs {

namespace {

const char kUsage[] =
	"Usage: coordinatord --world FILE [OPTIONS]\n"
	"       coordinatord --agent --dds-domain N [OPTIONS]\n"
	"Serve one simulated world to controllers attached with tcs-run --connect;\n"
	"as an agent, run controllers here for a world hosted on another machine.\n"
	"\n"
	"  -w, --world FILE       scenario; its [[controller]] entries are the\n"
	"                         controllers the world waits for before it starts\n"
	"  -s, --socket PATH      where to listen (default: $XDG_RUNTIME_DIR/tcs/\n"
	"                         coordinatord.sock, or /run/tcs/coordinatord.sock as root)\n"
	TCS_RUN_OPTIONS_HELP
	"  -t, --trace FILE       write a trace of everything served (MCAP)\n"
	"      --dds-domain N     publish rt/clock and rt/joint_states for ROS 2 tools\n"
	"                         on DDS domain N (0-232), one sample per step, and\n"
	"                         let agents on other hosts join the world there\n"
	"      --agent            join the world hosted on --dds-domain N; controllers\n"
	"                         attached here run here, in its step protocol\n"
	"      --name NAME        the agent's name (default: HOSTNAME-PID)\n"
	"  -q, --quiet            log only warnings and errors\n"
	"  -h, --help             show this help\n"
	"  -V, --version          show the version\n"
	"\n"
	"SIGTERM, SIGINT, SIGHUP or SIGQUIT ends it: controllers are ended, the\n"
	"trace is closed, the socket removed.\n"
	"Exit status: 0 after such an end, 2 for errors. See coordinatord(8).\n";

// The option combinations that make no daemon.
Status check_options(const DaemonOptions &o)
{
	if (o.agent && (o.dds_domain < 0 || !o.world_file.empty() || o.mode_given))
		return Error{ o.dds_domain < 0 ? "--agent needs --dds-domain N: where the world is hosted"
					       : "--agent takes the host's world and mode: no --world or --mode" };
	if (!o.agent && o.world_file.empty())
		return Error{ "--world FILE is required" };
	if (!o.agent && !o.agent_name.empty())
		return Error{ "--name is an agent's (--agent)" };
	return Ok{};
}

} // namespace

Result<DaemonOptions> parse_options(int argc, char **argv)
{
	enum { OPT_EPOCH = 256, OPT_DDS_DOMAIN, OPT_AGENT, OPT_NAME, OPT_NO_SLACK, OPT_SPIN_COST, OPT_SEED };
	static const struct option longopts[] = {
		{ "world", required_argument, nullptr, 'w' },
		{ "socket", required_argument, nullptr, 's' },
		{ "mode", required_argument, nullptr, 'm' },
		{ "trace", required_argument, nullptr, 't' },
		{ "epoch", required_argument, nullptr, OPT_EPOCH },
		{ "no-slack", no_argument, nullptr, OPT_NO_SLACK },
		{ "spin-cost", required_argument, nullptr, OPT_SPIN_COST },
		{ "seed", required_argument, nullptr, OPT_SEED },
		{ "dds-domain", required_argument, nullptr, OPT_DDS_DOMAIN },
		{ "agent", no_argument, nullptr, OPT_AGENT },
		{ "name", required_argument, nullptr, OPT_NAME },
		{ "quiet", no_argument, nullptr, 'q' },
		{ "help", no_argument, nullptr, 'h' },
		{ "version", no_argument, nullptr, 'V' },
		{ nullptr, 0, nullptr, 0 },
	};
	DaemonOptions o;
	int opt;
	opterr = 0;
	while ((opt = getopt_long(argc, argv, ":w:s:m:t:qhV", longopts, nullptr)) != -1) {
		std::string arg = optarg ? optarg : "";
		if (std::string name = run_option_of(longopts, opt); !name.empty()) {
			if (auto ok = set_run_option(name, arg, o.cfg); !ok)
				return ok.error();
			o.mode_given |= name == "mode";
			continue;
		}
		switch (opt) {
		case 'w':
			o.world_file = arg;
			break;
		case 's':
			o.socket_path = arg;
			break;
		case OPT_AGENT:
			o.agent = true;
			break;
		case OPT_NAME:
			o.agent_name = arg;
			break;
		case 't':
			o.cfg.trace_path = arg;
			break;
		case OPT_DDS_DOMAIN: {
			char *end = nullptr;
			long d = strtol(arg.c_str(), &end, 10);
			// DDS maps domains to UDP ports: 232 is the highest that fits.
			if (arg.empty() || *end || d < 0 || d > 232)
				return Error{ "--dds-domain: '" + arg + "' is not a domain id (0 to 232)" };
			o.dds_domain = (int)d;
			break;
		}
		case 'q':
			o.quiet = true;
			break;
		case 'h':
			o.help = true;
			return o;
		case 'V':
			o.version = true;
			return o;
		default:
			return Error{ getopt_complaint(opt, argv, optind) };
		}
	}
	if (optind < argc)
		return Error{ std::string("unexpected argument '") + argv[optind] +
			      "' (controllers attach with tcs-run --connect)" };
	if (auto ok = check_options(o); !ok)
		return ok.error();
	return o;
}

void print_help_or_version(const DaemonOptions &o)
{
	if (o.help)
		fputs(kUsage, stdout);
	else
		printf("coordinatord %s\n", TCS_VERSION);
}

} // namespace tcs
