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

int fail(const std::string &msg)
{
	return report_error("tcs-run", msg);
}

int usage_error(const std::string &msg)
{
	return report_usage_error("tcs-run", msg);
}

// --connect: the world, its mode, duration, trace and epoch are the
// daemon's; only the program and its CPU scale are the caller's.
int run_under_daemon(const std::string &socket, const std::vector<std::string> &given, int argc, char **argv,
		     double cpu_scale, bool quiet)
{
	if (!given.empty())
		return usage_error(given.front() + " cannot go with --connect: the world and its run are coordinatord's");
	if (argc == 0)
		return usage_error("--connect needs a PROGRAM to run");
	ConnectRequest req;
	req.socket = socket;
	req.argv.assign(argv, argv + argc);
	req.cpu_scale = cpu_scale;
	req.quiet = quiet;
	auto path = resolve_program(req.argv[0]);
	if (!path)
		return fail(path.error().message);
	if (auto ok = check_preloadable(*path); !ok)
		return fail(ok.error().message);
	req.path = *path;
	auto status = run_connected(req);
	if (!status)
		return fail(status.error().message);
	return *status;
}

} // namespace

// The scenario's wires, for --list-signals: each bus and what is on it.
static void print_wires(const WiresConfig &w)
{
	if (w.serials.empty() && w.i2cs.empty() && w.cans.empty())
		return;
	printf("wires\n");
	for (const SerialSpec &s : w.serials) {
		printf("  %-28s serial   %lld baud\n", s.path.c_str(), (long long)s.baud);
		for (const ServoSpec &v : s.servos)
			printf("    servo %-3u %-12s %s\n", v.id, v.protocol.c_str(), v.joint.name.c_str());
	}
	for (const I2cSpec &b : w.i2cs) {
		printf("  %-28s i2c      %lld Hz\n", ("/dev/i2c-" + std::to_string(b.bus)).c_str(), (long long)b.clock_hz);
		for (const I2cDeviceSpec &d : b.devices)
			printf("    0x%02x  %-12s %s\n", d.address, d.chip.c_str(), d.link.name.c_str());
	}
	for (const CanSpec &c : w.cans) {
		printf("  %-28s can      %lld bit/s%s\n", c.interface.c_str(), (long long)c.bitrate,
		       c.data_bitrate ? (", FD data " + std::to_string(c.data_bitrate) + " bit/s").c_str() : "");
		for (const CanMotorSpec &m : c.motors)
			printf("    motor 0x%03x %-10s %s\n", m.id, m.protocol.c_str(), m.joint.name.c_str());
		for (const CanFrameSpec &f : c.frames)
			printf("    frame 0x%03x %s, %zu fields\n", f.id, f.command ? "command" : "sensor", f.fields.size());
	}
}

int main(int argc, char **argv)
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
	CoordinatorConfig cfg;
	double cpu_scale = 1.0;
	bool quiet = false, list_signals = false, scale_given = false;
	std::string world_file, connect_socket, replay_file;
	std::vector<std::string> argv_owned; // --replay without a PROGRAM: the record's
	std::vector<std::string> given; // options that belong to the world's owner
	int opt;
	opterr = 0;
	while ((opt = getopt_long(argc, argv, "+:w:m:d:t:qhV", longopts, nullptr)) != -1) {
		std::string arg = optarg ? optarg : "";
		for (const struct option *o = longopts; o->name; o++)
			if (o->val == opt && (opt == 'w' || opt == 'm' || opt == 'd' || opt == 't' || opt == OPT_EPOCH ||
					      opt == OPT_LIST_SIGNALS || opt == OPT_NO_SLACK || opt == OPT_SPIN_COST ||
					      opt == OPT_SEED || opt == OPT_RECORD || opt == OPT_REPLAY))
				given.push_back(std::string("--") + o->name);
		if (std::string name = run_option_of(longopts, opt); !name.empty()) {
			if (auto ok = set_run_option(name, arg, cfg); !ok)
				return usage_error(ok.error().message);
			continue;
		}
		switch (opt) {
		case 'w':
			world_file = arg;
			break;
		case OPT_LIST_SIGNALS:
			list_signals = true;
			break;
		case OPT_CPU_SCALE: {
			auto v = parse_positive(arg);
			if (!v)
				return usage_error("--cpu-scale: " + v.error().message);
			cpu_scale = *v;
			scale_given = true;
			break;
		}
		case 'd': {
			auto v = parse_duration(arg);
			if (!v)
				return usage_error("--duration: " + v.error().message);
			if (*v <= 0)
				return usage_error("--duration: must be longer than zero");
			cfg.duration_ns = *v;
			break;
		}
		case 't':
			cfg.trace_path = arg;
			break;
		case OPT_RECORD:
			if (arg.empty())
				return usage_error("--record: the file's path is empty");
			cfg.record_path = arg;
			break;
		case OPT_REPLAY:
			if (arg.empty())
				return usage_error("--replay: the file's path is empty");
			replay_file = arg;
			break;
		case OPT_CONNECT:
			if (arg.empty())
				return usage_error("--connect: the socket's path is empty");
			connect_socket = arg;
			break;
		case 'q':
			quiet = true;
			break;
		case 'h':
			fputs(kUsage, stdout);
			return 0;
		case 'V':
			printf("tcs-run %s\n", TCS_VERSION);
			return 0;
		default:
			return usage_error(getopt_complaint(opt, argv, optind));
		}
	}
	if (!connect_socket.empty())
		return run_under_daemon(connect_socket, given, argc - optind, argv + optind, scale_given ? cpu_scale : 0, quiet);
	auto scenario = world_file.empty() ? default_scenario() : parse_scenario_file(world_file);
	if (!scenario)
		return fail(scenario.error().message);
	auto setup = world_setup(*scenario);
	if (!setup)
		return fail(setup.error().message);
	if (list_signals) {
		printf("%s: signals\n", world_file.empty() ? "built-in scenario" : world_file.c_str());
		for (const auto &line : setup->signal_lines)
			printf("  %s\n", line.c_str());
		printf("devices\n");
		for (const auto &d : setup->devices) {
			if (is_wire(d.kind))
				continue;
			std::string sigs;
			for (const auto &sig : d.signals)
				sigs += (sigs.empty() ? "" : " ") + sig;
			printf("  %-28s %-8s %-6s %s%s\n", d.path.c_str(),
			       d.kind == TCS_DEVICE_SENSOR ? "sensor" : "actuator",
			       d.format == TCS_FORMAT_TEXT ? "text" : "binary",
			       d.kind == TCS_DEVICE_ACTUATOR ? "" : d.latest ? "latest " : "stream ", sigs.c_str());
		}
		print_wires(setup->wires);
		return 0;
	}
	for (const auto &d : setup->devices)
		cfg.record_devices.push_back(d.path);
	if (!replay_file.empty()) {
		auto record = read_record(replay_file);
		if (!record)
			return fail(record.error().message);
		if (scale_given && cpu_scale != record->cpu_scale)
			return usage_error(format_number("--cpu-scale %g", cpu_scale) +
					   format_number(" differs from the record's %g (a replay takes the record's)",
							 record->cpu_scale));
		if (cfg.record_devices != record->devices)
			return fail(replay_file + ": recorded in another world (its devices differ from " +
				    (world_file.empty() ? std::string("the built-in scenario") : world_file) +
				    "'s): replay it with the record's scenario");
		if (optind == argc && scenario->controllers.empty()) {
			// The recorded program, as it was run.
			for (const auto &a : record->program)
				argv_owned.push_back(a);
		}
		if (cfg.seed && cfg.seed != record->seed)
			return usage_error("--seed differs from the record's (a replay takes the record's)");
		if (cfg.duration_ns < 0)
			cfg.duration_ns = record->duration_ns; // (as long as the recorded run, unless told)
		cpu_scale = record->cpu_scale; // (each controller's own: the coordinator's add_controller)
		cfg.replay = std::make_shared<const Record>(std::move(*record));
	}
	cfg.record_scale = cpu_scale;
	cfg.models = setup->models;
	cfg.devices = setup->devices;
	cfg.sensors = setup->sensors;
	cfg.wires = setup->wires;
	cfg.step_ns = setup->step_ns;

	for (int i = optind; i < argc; i++)
		argv_owned.push_back(argv[i]);
	std::vector<ControllerSpec> specs;
	if (!argv_owned.empty()) {
		ControllerSpec spec;
		spec.argv = argv_owned;
		spec.cpu_scale = cpu_scale;
		specs.push_back(spec);
		cfg.record_program = spec.argv;
	} else {
		for (const auto &entry : scenario->controllers) {
			ControllerSpec spec;
			spec.argv = entry.argv;
			spec.cpu_scale = entry.cpu_scale && !scale_given ? *entry.cpu_scale : cpu_scale;
			specs.push_back(spec);
		}
		if (specs.empty())
			return usage_error("no PROGRAM to run" +
					   std::string(world_file.empty() ? "" : " (and " + world_file + " names no [[controller]])"));
	}
	for (auto &spec : specs) {
		auto path = resolve_program(spec.argv[0]);
		if (!path && !world_file.empty() && spec.argv[0].find('/') != std::string::npos &&
		    spec.argv[0][0] != '/') {
			// A scenario's relative command: relative to the scenario's folder.
			std::string dir = world_file.substr(0, world_file.find_last_of('/') + 1);
			path = resolve_program(dir + spec.argv[0]);
		}
		if (!path)
			return fail(path.error().message);
		spec.path = *path;
		if (auto ok = check_preloadable(spec.path); !ok)
			return fail(ok.error().message);
	}
	auto preload = find_preload();
	if (!preload)
		return fail(preload.error().message);
	cfg.preload = *preload;
	cfg.realtime = realtime_wish_from_env();

	bool show_progress = !quiet && isatty(STDERR_FILENO);
	if (show_progress)
		cfg.on_progress = [](int64_t v, int64_t wall) {
			fprintf(stderr, "\r\033[K%s", progress_line(v, wall).c_str());
		};
	cfg.on_warning = [](const std::string &w) { fprintf(stderr, "tcs-run: warning: %s\n", w.c_str()); };

	auto co = Coordinator::create(cfg);
	if (!co)
		return fail(co.error().message);
	for (const auto &spec : specs)
		if (auto s = (*co)->add_controller(spec); !s)
			return fail("cannot start " + spec.argv[0] + ": " + s.error().message);
	auto report = (*co)->run();
	if (show_progress)
		fputs("\r\033[K", stderr);
	if (!report)
		return fail(report.error().message);
	if (!quiet)
		fputs(summary(*report, cfg.mode).c_str(), stderr);
	else
		fputs(drops(*report).c_str(), stderr); // (the summary says them too)
	return exit_status(*report);
}
