// coordinatord: one shared simulated world, served on a Unix socket to
// controllers attached with `tcs-run --connect`. The one place where the
// daemon's errors become messages and exit statuses.
#include <getopt.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>

#include "attach_socket.h"
#include "cli_errors.h"
#include "cli_time.h"
#include "run_options.h"
#include "clients.h"
#include "coordinator.h"
#include "preload_path.h"
#include "read_file.h"
#include "ros_bridge.h"
#include "step_link.h"
#include "run_report.h"
#include "scenario.h"
#include "sd_notify.h"
#include "world_setup.h"

using namespace tcs;

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

int fail(const std::string &msg)
{
	return report_error("coordinatord", msg);
}

int usage_error(const std::string &msg)
{
	return report_usage_error("coordinatord", msg);
}

void log_line(const std::string &msg)
{
	fprintf(stderr, "coordinatord: %s\n", msg.c_str());
}

std::string host_name()
{
	char name[256] = "";
	gethostname(name, sizeof name - 1);
	return name[0] ? name : "localhost";
}

// How long an agent waits for its world to be published.
constexpr int64_t kJoinWait = 30LL * 1000000000;
constexpr size_t kMaxScenario = 1 << 20;

} // namespace

int main(int argc, char **argv)
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
	CoordinatorConfig cfg;
	std::string world_file, socket_path;
	int dds_domain = -1;
	bool quiet = false, agent = false, mode_given = false;
	std::string agent_name;
	int opt;
	opterr = 0;
	while ((opt = getopt_long(argc, argv, ":w:s:m:t:qhV", longopts, nullptr)) != -1) {
		std::string arg = optarg ? optarg : "";
		if (std::string name = run_option_of(longopts, opt); !name.empty()) {
			if (auto ok = set_run_option(name, arg, cfg); !ok)
				return usage_error(ok.error().message);
			mode_given |= name == "mode";
			continue;
		}
		switch (opt) {
		case 'w':
			world_file = arg;
			break;
		case 's':
			socket_path = arg;
			break;
		case OPT_AGENT:
			agent = true;
			break;
		case OPT_NAME:
			agent_name = arg;
			break;
		case 't':
			cfg.trace_path = arg;
			break;
		case OPT_DDS_DOMAIN: {
			char *end = nullptr;
			long d = strtol(arg.c_str(), &end, 10);
			// DDS maps domains to UDP ports: 232 is the highest that fits.
			if (arg.empty() || *end || d < 0 || d > 232)
				return usage_error("--dds-domain: '" + arg + "' is not a domain id (0 to 232)");
			dds_domain = (int)d;
			break;
		}
		case 'q':
			quiet = true;
			break;
		case 'h':
			fputs(kUsage, stdout);
			return 0;
		case 'V':
			printf("coordinatord %s\n", TCS_VERSION);
			return 0;
		default:
			return usage_error(getopt_complaint(opt, argv, optind));
		}
	}
	if (optind < argc)
		return usage_error(std::string("unexpected argument '") + argv[optind] +
				   "' (controllers attach with tcs-run --connect)");
	if (agent && (dds_domain < 0 || !world_file.empty() || mode_given))
		return usage_error(dds_domain < 0 ? "--agent needs --dds-domain N: where the world is hosted"
						  : "--agent takes the host's world and mode: no --world or --mode");
	if (!agent && world_file.empty())
		return usage_error("--world FILE is required");
	if (!agent && !agent_name.empty())
		return usage_error("--name is an agent's (--agent)");

	// Before anything makes threads (DDS does): the signals that end the
	// daemon are the coordinator's to read from a signalfd, and threads made
	// before it takes SCHED_FIFO and its core keep the normal policy and
	// every CPU (ros_bridge.h).
	sigset_t ending;
	sigemptyset(&ending);
	for (int sig : { SIGINT, SIGTERM, SIGHUP, SIGQUIT })
		sigaddset(&ending, sig);
	pthread_sigmask(SIG_BLOCK, &ending, nullptr);

	// The world: from the file, or, for an agent, from its host.
	std::unique_ptr<StepAgent> agent_link;
	std::vector<pid_t> step_threads; // DDS's, for the step protocol
	std::string world_text, world_name = world_file;
	Result<Scenario> scenario = Error{ "" };
	if (agent) {
		if (agent_name.empty())
			agent_name = host_name() + "-" + std::to_string(getpid());
		if (!quiet)
			log_line("looking for a world on DDS domain " + std::to_string(dds_domain) + " (up to " +
				 std::to_string(kJoinWait / 1000000000) + " s)");
		auto joined = join_world((uint32_t)dds_domain, agent_name, kJoinWait);
		if (!joined)
			return fail("DDS domain " + std::to_string(dds_domain) + ": " + joined.error().message);
		agent_link = std::move(joined->link);
		step_threads = own_threads();
		world_name = "the world of " + joined->world.host;
		scenario = parse_scenario_text(joined->world.scenario, world_name);
		cfg.mode = joined->world.mode;
		cfg.step_agent = agent_link.get();
	} else {
		auto text = read_file(world_file, kMaxScenario);
		if (!text)
			return fail(text.error().message);
		world_text = *text;
		scenario = parse_scenario_file(world_file);
	}
	if (!scenario)
		return fail(scenario.error().message);
	auto setup = world_setup(*scenario);
	if (!setup)
		return fail(setup.error().message);
	if (agent)
		scenario->controllers.clear(); // the host waits for them, not we
	cfg.models = setup->models;
	cfg.devices = setup->devices;
	cfg.sensors = setup->sensors;
	cfg.step_ns = setup->step_ns;
	auto preload = find_preload();
	if (!preload)
		return fail(preload.error().message);
	cfg.preload = *preload;
	cfg.realtime = realtime_wish_from_env();
	cfg.serve = true;
	cfg.on_warning = [](const std::string &w) { log_line("warning: " + w); };
	auto log = [quiet](const std::string &msg) {
		if (!quiet)
			log_line(msg);
	};

	if (socket_path.empty()) {
		auto p = default_socket_path();
		if (!p)
			return fail(p.error().message);
		socket_path = *p;
	}
	auto listening = listen_socket(socket_path);
	if (!listening)
		return fail(listening.error().message);
	// From here, whatever ends the daemon takes its socket file with it.
	struct Unlink {
		std::string path;
		~Unlink() { unlink(path.c_str()); }
	} socket_file{ socket_path };

	std::unique_ptr<RosBridge> bridge;
	std::unique_ptr<StepHost> host_link;
	if (dds_domain >= 0 && !agent) {
		HostedWorldInfo w{ (uint32_t)getpid() ^ (uint32_t)time(nullptr), host_name(), world_text, cfg.mode };
		auto h = open_step_host((uint32_t)dds_domain, w);
		if (!h)
			return fail("DDS domain " + std::to_string(dds_domain) + ": " + h.error().message);
		host_link = std::move(*h);
		cfg.step_host = host_link.get();
		step_threads = own_threads();
		auto b = RosBridge::start((uint32_t)dds_domain, setup->joints);
		if (!b)
			return fail(b.error().message);
		bridge = std::move(*b);
		cfg.on_step = [&bridge](int64_t sim_ns, const SimWorld &world) { bridge->step(sim_ns, world); };
	}

	cfg.on_ending = [] { notify_systemd("STOPPING=1"); };
	Clients *clients = nullptr;
	cfg.on_controller_end = [&clients](const ControllerReport &r) {
		if (clients)
			clients->controller_ended(r);
	};
	cfg.on_agent_controllers = [&clients](const std::string &who, const std::vector<std::string> &programs) {
		if (clients)
			clients->agent_programs(who, programs);
	};
	cfg.on_info = log;
	auto co = Coordinator::create(cfg);
	if (!co)
		return fail(co.error().message);
	// The step protocol's DDS threads join the coordinator on its core
	// (at their normal priority): a barrier then costs a quarter of what it
	// does with them elsewhere (docs/PERFORMANCE.md). The main thread is
	// there already; the ROS bridge's threads stay off it.
	std::erase(step_threads, getpid());
	pin_threads(step_threads, (*co)->fifo_cpu());
	Clients served(**co, *scenario, log);
	clients = &served;
	if (auto s = served.serve(std::move(*listening)); !s)
		return fail(s.error().message);
	std::string waiting = served.waiting_for();
	log((agent ? "agent " + agent_name + " in " : "serving ") + world_name + " on " + socket_path +
	    (dds_domain >= 0 ? (agent ? ", by DDS domain " : " and on DDS domain ") + std::to_string(dds_domain) : "") +
	    (waiting.empty() ? "" : "; the world waits for " + waiting + " to attach"));
	notify_systemd("READY=1\nSTATUS=serving " + world_name + " on " + socket_path);

	auto report = (*co)->run();
	clients = nullptr;
	if (bridge) {
		uint64_t dropped = bridge->stop();
		if (dropped)
			log_line("warning: " + std::to_string(dropped) + " steps were not published on DDS (it fell behind)");
	}
	if (!report)
		return fail(report.error().message);
	if (!quiet)
		fputs(summary(*report, cfg.mode, "coordinatord").c_str(), stderr);
	if (report->reason == EndReason::Lost)
		return fail(report->lost);
	return 0;
}
