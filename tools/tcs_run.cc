// tcs-run: run an unmodified controller binary under virtual time.
// The one place where errors become messages and exit statuses.
#include <getopt.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli_errors.h"
#include "cli_time.h"
#include "run_options.h"
#include "connect_run.h"
#include "list_signals.h"
#include "coordinator.h"
#include "preload_path.h"
#include "program_check.h"
#include "run_report.h"
#include "default_scenario.h"
#include "record.h"
#include "scenario.h"
#include "world_setup.h"

using namespace tcs;

namespace {

const char kUsage[] =
	"Usage: tcs-run [OPTIONS] [--] PROGRAM [ARG...]\n"
	"       tcs-run -w SCENARIO [OPTIONS]      (runs the scenario's controllers)\n"
	"       tcs-run --replay RECORD [OPTIONS] [[--] PROGRAM [ARG...]]\n"
	"Run PROGRAM, unmodified, under virtual time beside a simulated world.\n"
	"\n"
	"  -w, --world FILE       scenario (default: the built-in pendulum)\n"
	"      --list-signals     print the scenario's signals and devices, and exit\n"
	TCS_RUN_OPTIONS_HELP
	"      --cpu-scale X      virtual seconds per CPU second (default 1.0;\n"
	"                         3 models a target CPU three times slower)\n"
	"  -d, --duration TIME    stop after TIME of virtual time (10s, 250ms, 2min)\n"
	"  -t, --trace FILE       write a trace of the run (MCAP)\n"
	"      --record FILE      record a cpu-mode run for --replay (a trace that also\n"
	"                         holds every clock value read and request's time)\n"
	"      --replay FILE      repeat a recorded run exactly (its scale, clocks and\n"
	"                         seed), saying where the program departs from it\n"
	"      --connect SOCKET   run under a running coordinatord\n"
	"  -q, --quiet            no progress line, no summary\n"
	"  -h, --help             show this help\n"
	"  -V, --version          show the version\n"
	"\n"
	"Exit status: the program's (128+N if signal N ended it), 0 when --duration\n"
	"ended the run, 2 for errors of tcs itself. See tcs-run(1).\n";

// A usage error: a mistake in the command line, told with where the help is.
struct Usage {
	std::string message;
};

// A step's Result that knows whether its error is a usage error.
template <class T> class [[nodiscard]] Step : public Result<T> {
public:
	Step(T value) : Result<T>(std::move(value)) {}
	Step(Error e) : Result<T>(std::move(e)) {}
	Step(Usage u) : Result<T>(Error{ std::move(u.message) }), usage_(true) {}
	bool usage() const { return usage_; }

private:
	bool usage_ = false;
};

// What the command line asks for.
struct Options {
	CoordinatorConfig cfg; // the run's options (--mode, --duration, --trace, --record, ...)
	double cpu_scale = 1.0;
	bool scale_given = false, quiet = false, list_signals = false, help = false, version = false;
	std::string world_file, connect_socket, replay_file;
	std::vector<std::string> given; // options that belong to the world's owner
	std::vector<std::string> program; // PROGRAM [ARG...]
};

// The scenario and what the coordinator runs of it.
struct World {
	Scenario scenario;
	WorldSetup setup;
};

// The run as it is put together: the coordinator's config and the controllers.
struct Plan {
	CoordinatorConfig cfg;
	double cpu_scale = 1.0; // the controllers' (a replay's: the record's)
	std::vector<std::string> program; // PROGRAM [ARG...] (a replay's without one: the record's)
	std::vector<ControllerSpec> specs;
	bool show_progress = false; // the progress line on stderr
};

} // namespace

// The one place an error becomes a message: "tcs-run: what" on stderr (a
// usage error adds where the help is), and exit status 2.
template <class T> static int report(const Step<T> &s)
{
	if (s.usage())
		return report_usage_error("tcs-run", s.error().message);
	return report_error("tcs-run", s.error().message);
}

// Reads the command line; all its errors are usage errors. --help and
// --version end the reading where getopt meets them.
static Step<Options> parse_options(int argc, char **argv)
{
	enum { OPT_CPU_SCALE = 256, OPT_EPOCH, OPT_CONNECT, OPT_LIST_SIGNALS, OPT_NO_SLACK, OPT_SPIN_COST, OPT_SEED,
	       OPT_RECORD, OPT_REPLAY };
	static const struct option longopts[] = {
		{ "world", required_argument, nullptr, 'w' },
		{ "mode", required_argument, nullptr, 'm' },
		{ "cpu-scale", required_argument, nullptr, OPT_CPU_SCALE },
		{ "duration", required_argument, nullptr, 'd' },
		{ "trace", required_argument, nullptr, 't' },
		{ "epoch", required_argument, nullptr, OPT_EPOCH },
		{ "no-slack", no_argument, nullptr, OPT_NO_SLACK },
		{ "spin-cost", required_argument, nullptr, OPT_SPIN_COST },
		{ "seed", required_argument, nullptr, OPT_SEED },
		{ "record", required_argument, nullptr, OPT_RECORD },
		{ "replay", required_argument, nullptr, OPT_REPLAY },
		{ "connect", required_argument, nullptr, OPT_CONNECT },
		{ "list-signals", no_argument, nullptr, OPT_LIST_SIGNALS },
		{ "quiet", no_argument, nullptr, 'q' },
		{ "help", no_argument, nullptr, 'h' },
		{ "version", no_argument, nullptr, 'V' },
		{ nullptr, 0, nullptr, 0 },
	};
	Options o;
	int opt;
	opterr = 0;
	while ((opt = getopt_long(argc, argv, "+:w:m:d:t:qhV", longopts, nullptr)) != -1) {
		std::string arg = optarg ? optarg : "";
		for (const struct option *l = longopts; l->name; l++)
			if (l->val == opt && (opt == 'w' || opt == 'm' || opt == 'd' || opt == 't' || opt == OPT_EPOCH ||
					      opt == OPT_LIST_SIGNALS || opt == OPT_NO_SLACK || opt == OPT_SPIN_COST ||
					      opt == OPT_SEED || opt == OPT_RECORD || opt == OPT_REPLAY))
				o.given.push_back(std::string("--") + l->name);
		if (std::string name = run_option_of(longopts, opt); !name.empty()) {
			if (auto ok = set_run_option(name, arg, o.cfg); !ok)
				return Usage{ ok.error().message };
			continue;
		}
		switch (opt) {
		case 'w':
			o.world_file = arg;
			break;
		case OPT_LIST_SIGNALS:
			o.list_signals = true;
			break;
		case OPT_CPU_SCALE: {
			auto v = parse_positive(arg);
			if (!v)
				return Usage{ "--cpu-scale: " + v.error().message };
			o.cpu_scale = *v;
			o.scale_given = true;
			break;
		}
		case 'd': {
			auto v = parse_duration(arg);
			if (!v)
				return Usage{ "--duration: " + v.error().message };
			if (*v <= 0)
				return Usage{ "--duration: must be longer than zero" };
			o.cfg.duration_ns = *v;
			break;
		}
		case 't':
			o.cfg.trace_path = arg;
			break;
		case OPT_RECORD:
			if (arg.empty())
				return Usage{ "--record: the file's path is empty" };
			o.cfg.record_path = arg;
			break;
		case OPT_REPLAY:
			if (arg.empty())
				return Usage{ "--replay: the file's path is empty" };
			o.replay_file = arg;
			break;
		case OPT_CONNECT:
			if (arg.empty())
				return Usage{ "--connect: the socket's path is empty" };
			o.connect_socket = arg;
			break;
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
			return Usage{ getopt_complaint(opt, argv, optind) };
		}
	}
	o.program.assign(argv + optind, argv + argc);
	return o;
}

// --help or --version: its text on stdout.
static void show_help_or_version(const Options &o)
{
	if (o.help)
		fputs(kUsage, stdout);
	else
		printf("tcs-run %s\n", TCS_VERSION);
}

// A controller's command as execvp would find it (a scenario's relative one
// not found so: relative to the scenario's folder), checked to take tcs's runtime.
static Step<std::string> checked_program(const std::string &command, const std::string &world_file)
{
	auto path = resolve_program(command);
	if (!path && !world_file.empty() && command.find('/') != std::string::npos && command[0] != '/') {
		std::string dir = world_file.substr(0, world_file.find_last_of('/') + 1);
		path = resolve_program(dir + command);
	}
	if (!path)
		return path.error();
	if (auto ok = check_preloadable(*path); !ok)
		return ok.error();
	return *path;
}

// --connect: the world, its mode, duration, trace and epoch are the
// daemon's; only the program and its CPU scale are the caller's. The value
// is the exit status.
static Step<int> run_under_daemon(const Options &o)
{
	if (!o.given.empty())
		return Usage{ o.given.front() + " cannot go with --connect: the world and its run are coordinatord's" };
	if (o.program.empty())
		return Usage{ "--connect needs a PROGRAM to run" };
	ConnectRequest req;
	req.socket = o.connect_socket;
	req.argv = o.program;
	req.cpu_scale = o.scale_given ? o.cpu_scale : 0;
	req.quiet = o.quiet;
	auto path = checked_program(req.argv[0], ""); // (no scenario: -w does not go with --connect)
	if (!path)
		return path.error();
	req.path = *path;
	auto status = run_connected(req);
	if (!status)
		return status.error();
	return *status;
}

// The scenario (-w's, or the built-in pendulum) and its setup for the coordinator.
static Step<World> load_world(const std::string &world_file)
{
	auto scenario = world_file.empty() ? default_scenario() : parse_scenario_file(world_file);
	if (!scenario)
		return scenario.error();
	auto setup = world_setup(*scenario);
	if (!setup)
		return setup.error();
	return World{ std::move(*scenario), std::move(*setup) };
}

// The run as the command line and the world set it: the options' config
// with the world's models, devices, sensors, wires and step.
static Plan world_plan(const Options &o, const WorldSetup &setup)
{
	Plan plan;
	plan.cfg = o.cfg;
	for (const auto &d : setup.devices)
		plan.cfg.record_devices.push_back(d.path);
	plan.cfg.models = setup.models;
	plan.cfg.devices = setup.devices;
	plan.cfg.sensors = setup.sensors;
	plan.cfg.wires = setup.wires;
	plan.cfg.step_ns = setup.step_ns;
	plan.cpu_scale = o.cpu_scale;
	plan.program = o.program;
	return plan;
}

// --replay: the record, which must agree with the command line and have the
// world's devices, gives the run its scale, seed and duration, and its
// program when neither the command line nor the scenario names one.
static Step<Ok> follow_replay(const Options &o, const Scenario &scenario, Plan &plan)
{
	if (o.replay_file.empty())
		return Ok{};
	auto record = read_record(o.replay_file);
	if (!record)
		return record.error();
	if (o.scale_given && o.cpu_scale != record->cpu_scale)
		return Usage{ format_number("--cpu-scale %g", o.cpu_scale) +
			      format_number(" differs from the record's %g (a replay takes the record's)", record->cpu_scale) };
	if (plan.cfg.record_devices != record->devices)
		return Error{ o.replay_file + ": recorded in another world (its devices differ from " +
			      (o.world_file.empty() ? std::string("the built-in scenario") : o.world_file) +
			      "'s): replay it with the record's scenario" };
	if (o.program.empty() && scenario.controllers.empty())
		plan.program = record->program; // the recorded program, as it was run
	if (plan.cfg.seed && plan.cfg.seed != record->seed)
		return Usage{ "--seed differs from the record's (a replay takes the record's)" };
	if (plan.cfg.duration_ns < 0)
		plan.cfg.duration_ns = record->duration_ns; // (as long as the recorded run, unless told)
	plan.cpu_scale = record->cpu_scale; // (each controller's own: the coordinator's add_controller)
	plan.cfg.replay = std::make_shared<const Record>(std::move(*record));
	return Ok{};
}

// The controllers: PROGRAM, or else the scenario's [[controller]]s (each at
// its own cpu_scale unless --cpu-scale is given); what --record keeps of them.
static Step<Ok> choose_controllers(const Options &o, const Scenario &scenario, Plan &plan)
{
	plan.cfg.record_scale = plan.cpu_scale;
	if (!plan.program.empty()) {
		ControllerSpec spec;
		spec.argv = plan.program;
		spec.cpu_scale = plan.cpu_scale;
		plan.specs.push_back(spec);
		plan.cfg.record_program = spec.argv;
		return Ok{};
	}
	for (const auto &entry : scenario.controllers) {
		ControllerSpec spec;
		spec.argv = entry.argv;
		spec.cpu_scale = entry.cpu_scale && !o.scale_given ? *entry.cpu_scale : plan.cpu_scale;
		plan.specs.push_back(spec);
	}
	if (plan.specs.empty())
		return Usage{ "no PROGRAM to run" +
			      std::string(o.world_file.empty() ? "" : " (and " + o.world_file + " names no [[controller]])") };
	return Ok{};
}

// Each controller's program found and able to take tcs's runtime, before any starts.
static Step<Ok> check_programs(const std::string &world_file, std::vector<ControllerSpec> &specs)
{
	for (auto &spec : specs) {
		auto path = checked_program(spec.argv[0], world_file);
		if (!path)
			return path.error();
		spec.path = *path;
	}
	return Ok{};
}

// The rest of the coordinator's config: the runtime it preloads, the
// real-time wish, and the progress line and warnings it shows on stderr.
static Step<Ok> finish_config(bool quiet, Plan &plan)
{
	auto preload = find_preload();
	if (!preload)
		return preload.error();
	plan.cfg.preload = *preload;
	plan.cfg.realtime = realtime_wish_from_env();

	plan.show_progress = !quiet && isatty(STDERR_FILENO);
	if (plan.show_progress)
		plan.cfg.on_progress = [](int64_t v, int64_t wall) {
			fprintf(stderr, "\r\033[K%s", progress_line(v, wall).c_str());
		};
	plan.cfg.on_warning = [](const std::string &w) { fprintf(stderr, "tcs-run: warning: %s\n", w.c_str()); };
	return Ok{};
}

// Starts the controllers beside the world and runs them to the run's end; the
// progress line is cleared however the run ends.
static Step<RunReport> run_controllers(const Plan &plan)
{
	auto co = Coordinator::create(plan.cfg);
	if (!co)
		return co.error();
	for (const auto &spec : plan.specs)
		if (auto s = (*co)->add_controller(spec); !s)
			return Error{ "cannot start " + spec.argv[0] + ": " + s.error().message };
	auto report = (*co)->run();
	if (plan.show_progress)
		fputs("\r\033[K", stderr);
	if (!report)
		return report.error();
	return std::move(*report);
}

// The run's summary on stderr; with -q only the controllers tcs dropped (the summary says them too).
static void tell_outcome(const RunReport &report, bool quiet, int mode)
{
	if (!quiet)
		fputs(summary(report, mode).c_str(), stderr);
	else
		fputs(drops(report).c_str(), stderr);
}

int main(int argc, char **argv)
{
	auto opts = parse_options(argc, argv);
	if (!opts)
		return report(opts);
	if (opts->help || opts->version) {
		show_help_or_version(*opts);
		return 0;
	}
	if (!opts->connect_socket.empty()) {
		auto status = run_under_daemon(*opts);
		return status ? *status : report(status);
	}
	auto world = load_world(opts->world_file);
	if (!world)
		return report(world);
	if (opts->list_signals) {
		print_signals(opts->world_file, world->setup);
		return 0;
	}
	Plan plan = world_plan(*opts, world->setup);
	if (auto ok = follow_replay(*opts, world->scenario, plan); !ok)
		return report(ok);
	if (auto ok = choose_controllers(*opts, world->scenario, plan); !ok)
		return report(ok);
	if (auto ok = check_programs(opts->world_file, plan.specs); !ok)
		return report(ok);
	if (auto ok = finish_config(opts->quiet, plan); !ok)
		return report(ok);
	auto run = run_controllers(plan);
	if (!run)
		return report(run);
	tell_outcome(*run, opts->quiet, plan.cfg.mode);
	return exit_status(*run);
}
