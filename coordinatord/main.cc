// coordinatord: one shared simulated world, served on a Unix socket to
// controllers attached with `tcs-run --connect`. The one place where the
// daemon's errors become messages and exit statuses.
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "attach_socket.h"
#include "cli_errors.h"
#include "cli_time.h"
#include "clients.h"
#include "coordinator.h"
#include "daemon_options.h"
#include "preload_path.h"
#include "read_file.h"
#include "ros_bridge.h"
#include "step_link.h"
#include "run_report.h"
#include "scenario.h"
#include "sd_notify.h"
#include "unique_fd.h"
#include "world_setup.h"

using namespace tcs;

namespace {

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

// The world served: from the scenario file, or, for an agent, from its host.
struct World {
	std::unique_ptr<StepAgent> agent_link;
	std::vector<pid_t> step_threads; // DDS's, for the step protocol
	std::string text, name;          // text: the file's, for agents to take
	Scenario scenario;
	WorldSetup setup;
};

// Removes the socket file when the daemon ends, however it ends.
struct SocketFile {
	std::string path;
	~SocketFile()
	{
		if (!path.empty())
			unlink(path.c_str());
	}
};

// The socket controllers attach to, and its file.
struct Listening {
	UniqueFd fd;
	SocketFile file;
};

// A hosted world on DDS: the step protocol's host end and the ROS 2 bridge.
struct Dds {
	std::unique_ptr<RosBridge> bridge;
	std::unique_ptr<StepHost> host_link;
};

// The coordinator and the clients it serves.
struct Serving {
	Clients *clients = nullptr; // for the coordinator's callbacks, while it runs
	std::unique_ptr<Coordinator> co;
	std::optional<Clients> served;
};

// The daemon's log of what it does: nothing of it with --quiet.
Clients::Log info_log(bool quiet)
{
	return [quiet](const std::string &msg) {
		if (!quiet)
			log_line(msg);
	};
}

// Blocks the signals that end the daemon: the coordinator reads them from a signalfd.
void block_ending_signals()
{
	sigset_t ending;
	sigemptyset(&ending);
	for (int sig : { SIGINT, SIGTERM, SIGHUP, SIGQUIT })
		sigaddset(&ending, sig);
	pthread_sigmask(SIG_BLOCK, &ending, nullptr);
}

// An agent's world: waits for the one hosted on its DDS domain, takes its scenario and mode.
Result<Scenario> join_hosted_world(DaemonOptions &o, World &w)
{
	if (o.agent_name.empty())
		o.agent_name = host_name() + "-" + std::to_string(getpid());
	if (!o.quiet)
		log_line("looking for a world on DDS domain " + std::to_string(o.dds_domain) + " (up to " +
			 std::to_string(kJoinWait / 1000000000) + " s)");
	auto joined = join_world((uint32_t)o.dds_domain, o.agent_name, kJoinWait);
	if (!joined)
		return Error{ "DDS domain " + std::to_string(o.dds_domain) + ": " + joined.error().message };
	w.agent_link = std::move(joined->link);
	w.step_threads = own_threads();
	w.name = "the world of " + joined->world.host;
	auto scenario = parse_scenario_text(joined->world.scenario, w.name);
	o.cfg.mode = joined->world.mode;
	o.cfg.step_agent = w.agent_link.get();
	return scenario;
}

// A host's world: the scenario file, its text kept for agents to take.
Result<Scenario> read_world_file(const DaemonOptions &o, World &w)
{
	auto text = read_file(o.world_file, kMaxScenario);
	if (!text)
		return text.error();
	w.text = *text;
	return parse_scenario_file(o.world_file);
}

// Loads the world, from its file or its host, and sets it up for the coordinator.
Status load_world(DaemonOptions &o, World &w)
{
	w.name = o.world_file;
	auto scenario = o.agent ? join_hosted_world(o, w) : read_world_file(o, w);
	if (!scenario)
		return scenario.error();
	w.scenario = std::move(*scenario);
	auto setup = world_setup(w.scenario);
	if (!setup)
		return setup.error();
	w.setup = std::move(*setup);
	if (o.agent)
		w.scenario.controllers.clear(); // the host waits for them, not we
	return Ok{};
}

// Fills the coordinator's configuration: the world, the preload library, the realtime wish.
Status configure_run(const World &world, CoordinatorConfig &cfg)
{
	cfg.models = world.setup.models;
	cfg.devices = world.setup.devices;
	cfg.sensors = world.setup.sensors;
	cfg.step_ns = world.setup.step_ns;
	auto preload = find_preload();
	if (!preload)
		return preload.error();
	cfg.preload = *preload;
	cfg.realtime = realtime_wish_from_env();
	cfg.serve = true;
	cfg.on_warning = [](const std::string &w) { log_line("warning: " + w); };
	return Ok{};
}

// Listens on --socket, or the default path when none was given.
Status listen_on(std::string &socket_path, Listening &l)
{
	if (socket_path.empty()) {
		auto p = default_socket_path();
		if (!p)
			return p.error();
		socket_path = *p;
	}
	auto fd = listen_socket(socket_path);
	if (!fd)
		return fd.error();
	l.fd = std::move(*fd);
	l.file.path = socket_path;
	return Ok{};
}

// Hosts the world on --dds-domain for agents elsewhere, and starts the ROS 2 bridge there.
Status host_on_dds(DaemonOptions &o, World &w, Dds &d)
{
	HostedWorldInfo info{ (uint32_t)getpid() ^ (uint32_t)time(nullptr), host_name(), w.text, o.cfg.mode };
	auto h = open_step_host((uint32_t)o.dds_domain, info);
	if (!h)
		return Error{ "DDS domain " + std::to_string(o.dds_domain) + ": " + h.error().message };
	d.host_link = std::move(*h);
	o.cfg.step_host = d.host_link.get();
	w.step_threads = own_threads();
	auto b = RosBridge::start((uint32_t)o.dds_domain, w.setup.joints);
	if (!b)
		return b.error();
	d.bridge = std::move(*b);
	o.cfg.on_step = [&bridge = d.bridge](int64_t sim_ns, const SimWorld &world) { bridge->step(sim_ns, world); };
	return Ok{};
}

// Creates the coordinator, its callbacks reaching the clients while they are served.
Status create_coordinator(DaemonOptions &o, Serving &s)
{
	o.cfg.on_ending = [] { notify_systemd("STOPPING=1"); };
	o.cfg.on_controller_end = [&clients = s.clients](const ControllerReport &r) {
		if (clients)
			clients->controller_ended(r);
	};
	o.cfg.on_agent_controllers = [&clients = s.clients](const std::string &who,
							    const std::vector<std::string> &programs) {
		if (clients)
			clients->agent_programs(who, programs);
	};
	o.cfg.on_info = info_log(o.quiet);
	auto co = Coordinator::create(o.cfg);
	if (!co)
		return co.error();
	s.co = std::move(*co);
	return Ok{};
}

// Puts the step protocol's DDS threads on the coordinator's core.
void pin_step_threads(std::vector<pid_t> &step_threads, int cpu)
{
	// They join it at their normal priority: a barrier then costs a quarter
	// of what it does with them elsewhere (docs/PERFORMANCE.md). The main
	// thread is there already; the ROS bridge's threads stay off it.
	std::erase(step_threads, getpid());
	pin_threads(step_threads, cpu);
}

// Serves the listening socket's clients from the coordinator's loop.
Status serve_clients(const DaemonOptions &o, const World &w, Listening &l, Serving &s)
{
	s.served.emplace(*s.co, w.scenario, info_log(o.quiet));
	s.clients = &*s.served;
	return s.served->serve(std::move(l.fd));
}

// Says what is served where, to the log and to systemd (READY=1).
void announce(const DaemonOptions &o, const World &w, const Serving &s)
{
	std::string msg = (o.agent ? "agent " + o.agent_name + " in " : "serving ") + w.name + " on " + o.socket_path;
	if (o.dds_domain >= 0)
		msg += (o.agent ? ", by DDS domain " : " and on DDS domain ") + std::to_string(o.dds_domain);
	std::string waiting = s.served->waiting_for();
	if (!waiting.empty())
		msg += "; the world waits for " + waiting + " to attach";
	if (!o.quiet)
		log_line(msg);
	notify_systemd("READY=1\nSTATUS=serving " + w.name + " on " + o.socket_path);
}

// Runs the world to its end, stops the ROS 2 bridge, sums the run up; a lost peer is an error.
Status run_to_end(const DaemonOptions &o, Dds &d, Serving &s)
{
	auto report = s.co->run();
	s.clients = nullptr;
	if (d.bridge) {
		uint64_t dropped = d.bridge->stop();
		if (dropped)
			log_line("warning: " + std::to_string(dropped) + " steps were not published on DDS (it fell behind)");
	}
	if (!report)
		return report.error();
	if (!o.quiet)
		fputs(summary(*report, o.cfg.mode, "coordinatord").c_str(), stderr);
	if (report->reason == EndReason::Lost)
		return Error{ report->lost };
	return Ok{};
}

} // namespace

// The daemon's steps. What they hold lives here, in main, until its end:
// an error is reported before any of it is torn down, and it is torn down
// in the reverse of the order it was made.
int main(int argc, char **argv)
{
	auto parsed = parse_options(argc, argv);
	if (!parsed)
		return usage_error(parsed.error().message);
	DaemonOptions &o = *parsed;
	if (o.help || o.version) {
		print_help_or_version(o);
		return 0;
	}
	// Before anything makes threads (DDS does): they inherit the mask.
	block_ending_signals();
	World world;
	if (auto s = load_world(o, world); !s)
		return fail(s.error().message);
	if (auto s = configure_run(world, o.cfg); !s)
		return fail(s.error().message);
	Listening listening;
	if (auto s = listen_on(o.socket_path, listening); !s)
		return fail(s.error().message);
	// Before the coordinator takes SCHED_FIFO and its core: threads made
	// earlier keep the normal policy and every CPU (ros_bridge.h).
	Dds dds;
	if (o.dds_domain >= 0 && !o.agent) {
		if (auto s = host_on_dds(o, world, dds); !s)
			return fail(s.error().message);
	}
	Serving serving;
	if (auto s = create_coordinator(o, serving); !s)
		return fail(s.error().message);
	pin_step_threads(world.step_threads, serving.co->fifo_cpu());
	if (auto s = serve_clients(o, world, listening, serving); !s)
		return fail(s.error().message);
	announce(o, world, serving);
	if (auto s = run_to_end(o, dds, serving); !s)
		return fail(s.error().message);
	return 0;
}
