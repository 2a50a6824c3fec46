// tcs-trace: inspect a trace written by tcs-run --trace (docs/DESIGN.md §6).
// The one place where errors become messages and exit statuses.
#include <getopt.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "cli_errors.h"
#include "trace_data.h"
#include "trace_export.h"
#include "trace_plot.h"
#include "trace_summary.h"

using namespace tcs;

namespace {

const char kUsage[] =
	"Usage: tcs-trace summary [--json] FILE\n"
	"       tcs-trace export FILE --format csv|json|chrome|candump [--topic TOPIC] [-o OUT]\n"
	"       tcs-trace plot FILE -o OUT.png|OUT.svg [--kind timing|disparity|error|joints]\n"
	"Inspect a trace written by tcs-run --trace (an MCAP file).\n"
	"\n"
	"  summary   per controller: cycles, loop rate, period p50/p99/max, deadline\n"
	"            misses, preemptions and their overshoot, charged CPU; per run:\n"
	"            virtual and wall time, real-time factor, step wall cost, timing error\n"
	"      --json             the same figures as one JSON object\n"
	"  export    write the trace in another format (to OUT, default stdout)\n"
	"  -f, --format csv       one topic's messages, fields as columns (--topic,\n"
	"                         default /tcs/slice)\n"
	"           json          every message with its topic and log time\n"
	"           chrome        Trace Event JSON for Perfetto / chrome://tracing\n"
	"           candump       the CAN frames as candump's log (candump -L, canplayer)\n"
	"      --topic TOPIC      only this topic (/tcs/slice, /tcs/wait, /tcs/device,\n"
	"                         /tcs/step, /tcs/controller, /clock, and a wire's\n"
	"                         /tcs/wire/can0, /tcs/wire/dev/ttyUSB0, /tcs/wire/dev/i2c-1)\n"
	"  plot      draw with gnuplot into OUT (.png or .svg)\n"
	"  -k, --kind timing      controller time against simulation time (default)\n"
	"           disparity     controller time minus simulation time\n"
	"           error         aggregate relative timing error\n"
	"           joints        joint positions and velocities\n"
	"  -o, --output OUT       where to write\n"
	"  -h, --help             show this help\n"
	"  -V, --version          show the version\n"
	"\n"
	"Exit status: 0 on success, 2 on any error. See tcs-trace(1).\n";

int fail(const std::string &msg)
{
	return report_error("tcs-trace", msg);
}

int usage_error(const std::string &msg)
{
	return report_usage_error("tcs-trace", msg);
}

// Writes through a temporary file renamed into place on success, so a
// failed export never leaves half a file under the name asked for.
class Output {
public:
	Status open(const std::string &path)
	{
		path_ = path;
		if (path.empty() || path == "-") {
			f_ = stdout;
			return Ok{};
		}
		tmp_ = path + ".tmp-" + std::to_string(getpid());
		f_ = fopen(tmp_.c_str(), "w");
		if (!f_)
			return errno_error(path);
		return Ok{};
	}
	FILE *file() { return f_; }
	Status commit()
	{
		if (f_ == stdout)
			return fflush(stdout) == 0 ? Status(Ok{}) : Status(errno_error("standard output"));
		bool ok = !ferror(f_);
		ok = fclose(f_) == 0 && ok;
		f_ = nullptr;
		if (!ok || rename(tmp_.c_str(), path_.c_str()) != 0) {
			int err = errno;
			unlink(tmp_.c_str());
			return errno_error(path_, err ? err : EIO);
		}
		return Ok{};
	}
	~Output()
	{
		if (f_ && f_ != stdout) {
			fclose(f_);
			unlink(tmp_.c_str());
		}
	}

private:
	std::string path_, tmp_;
	FILE *f_ = nullptr;
};

} // namespace

int main(int argc, char **argv)
{
	enum { OPT_JSON = 256, OPT_TOPIC };
	static const option longopts[] = {
		{ "json", no_argument, nullptr, OPT_JSON },
		{ "format", required_argument, nullptr, 'f' },
		{ "topic", required_argument, nullptr, OPT_TOPIC },
		{ "kind", required_argument, nullptr, 'k' },
		{ "output", required_argument, nullptr, 'o' },
		{ "help", no_argument, nullptr, 'h' },
		{ "version", no_argument, nullptr, 'V' },
		{ nullptr, 0, nullptr, 0 },
	};
	bool json = false;
	std::string format, topic, kind, output;
	bool have_kind = false, have_format = false;
	int opt;
	while ((opt = getopt_long(argc, argv, "f:k:o:hV", longopts, nullptr)) != -1) {
		switch (opt) {
		case OPT_JSON:
			json = true;
			break;
		case 'f':
			format = optarg;
			have_format = true;
			break;
		case OPT_TOPIC:
			topic = optarg;
			break;
		case 'k':
			kind = optarg;
			have_kind = true;
			break;
		case 'o':
			output = optarg;
			break;
		case 'h':
			fputs(kUsage, stdout);
			return 0;
		case 'V':
			printf("tcs-trace %s\n", TCS_VERSION);
			return 0;
		default:
			return usage_error("bad option");
		}
	}
	if (optind >= argc)
		return usage_error("no command: summary, export or plot");
	std::string cmd = argv[optind++];
	if (cmd != "summary" && cmd != "export" && cmd != "plot")
		return usage_error("unknown command '" + cmd + "' (summary, export or plot)");
	if (optind >= argc)
		return usage_error("no trace file given");
	if (argc - optind > 1)
		return usage_error("one trace file at a time ('" + std::string(argv[optind + 1]) + "' is extra)");
	std::string path = argv[optind];
	if (cmd != "summary" && json)
		return usage_error("--json is for summary");
	if (cmd != "export" && (have_format || !topic.empty()))
		return usage_error("--format and --topic are for export");
	if (cmd != "plot" && have_kind)
		return usage_error("--kind is for plot");
	if (cmd == "summary" && !output.empty())
		return usage_error("summary prints to standard output; --output is for export and plot");

	if (cmd == "summary") {
		auto t = load_trace(path);
		if (!t)
			return fail(t.error().message);
		RunSummary s = summarize(*t);
		fputs((json ? summary_json(s) : summary_text(s)).c_str(), stdout);
		return fflush(stdout) == 0 ? 0 : fail("standard output: " + std::string(strerror(errno)));
	}
	if (cmd == "export") {
		ExportFormat f;
		if (format == "csv")
			f = ExportFormat::Csv;
		else if (format == "json")
			f = ExportFormat::Json;
		else if (format == "chrome")
			f = ExportFormat::Chrome;
		else if (format == "candump")
			f = ExportFormat::Candump;
		else if (!have_format)
			return usage_error("export needs --format csv, json, chrome or candump");
		else
			return usage_error("unknown format '" + format + "' (csv, json, chrome or candump)");
		if (f == ExportFormat::Csv && topic.empty())
			topic = "/tcs/slice";
		if (f == ExportFormat::Chrome && !topic.empty())
			return usage_error("--topic is for csv, json and candump (chrome shows every topic)");
		// Read before the output is created: a bad trace leaves nothing behind.
		if (access(path.c_str(), R_OK) != 0)
			return fail(path + ": " + strerror(errno));
		Output out;
		if (auto s = out.open(output); !s)
			return fail(s.error().message);
		if (auto s = export_trace(path, f, topic, out.file()); !s)
			return fail(s.error().message);
		if (auto s = out.commit(); !s)
			return fail(s.error().message);
		return 0;
	}
	PlotKind k = PlotKind::Timing;
	if (kind == "disparity")
		k = PlotKind::Disparity;
	else if (kind == "error")
		k = PlotKind::Error;
	else if (kind == "joints")
		k = PlotKind::Joints;
	else if (have_kind && kind != "timing")
		return usage_error("unknown plot kind '" + kind + "' (timing, disparity, error or joints)");
	if (output.empty())
		return usage_error("plot needs -o OUT.png or OUT.svg");
	auto t = load_trace(path);
	if (!t)
		return fail(t.error().message);
	if (auto s = plot_trace(*t, k, output); !s)
		return fail(s.error().message);
	return 0;
}
