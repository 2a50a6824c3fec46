// plot_trace: writes the data and a gnuplot script into a private temporary
// directory, runs gnuplot (found on PATH) and checks that it made the image.
#include "trace_plot.h"

#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

namespace tcs {

namespace {

// A directory removed with everything in it when it goes.
class TempDir {
public:
	Status create()
	{
		const char *tmp = getenv("TMPDIR");
		std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/tcs-trace-plot-XXXXXX";
		if (!mkdtemp(templ.data()))
			return errno_error("cannot create a temporary directory in " + templ.substr(0, templ.rfind('/')));
		path_ = templ;
		return Ok{};
	}
	~TempDir()
	{
		for (const auto &f : files_)
			unlink(f.c_str());
		if (!path_.empty())
			rmdir(path_.c_str());
	}
	std::string file(const std::string &name)
	{
		files_.push_back(path_ + "/" + name);
		return files_.back();
	}

private:
	std::string path_;
	std::vector<std::string> files_;
};

// gnuplot string literal: single quotes, doubled inside.
std::string quoted(const std::string &s)
{
	std::string o = "'";
	for (char c : s) {
		if (c == '\'')
			o += '\'';
		o += c;
	}
	return o + "'";
}

// Title text: gnuplot's enhanced mode would read _ and ^ as markup.
std::string plain(const std::string &s)
{
	std::string o;
	for (char c : s) {
		if (c == '_' || c == '^' || c == '{' || c == '}' || c == '@' || c == '&' || c == '~')
			o += '\\';
		o += c;
	}
	return o;
}

struct Series {
	std::string title;
	std::string data; // "x y\n" lines
};

Result<std::vector<Series>> series_for(const TraceData &t, PlotKind kind)
{
	std::vector<Series> out;
	char line[96];
	if (kind == PlotKind::Joints) {
		if (t.joint_names.empty() || t.steps.empty())
			return Error{ t.path + ": no joint states to plot (the run had no world, or no joints)" };
		for (size_t j = 0; j < t.joint_names.size(); j++) {
			Series s{ t.joint_names[j], "" };
			for (const auto &st : t.steps)
				if (j < st.joints.size() && std::isfinite(st.joints[j])) {
					snprintf(line, sizeof line, "%.9f %.9g\n", (double)st.v / 1e9, st.joints[j]);
					s.data += line;
				}
			out.push_back(std::move(s));
		}
		return out;
	}
	for (const auto &c : t.controllers) {
		Series s{ "controller " + std::to_string(c.id) + ": " + c.name, "" };
		double computing = 0, charged = 0;
		for (const auto &sl : t.slices) {
			if (sl.controller != c.id)
				continue;
			double S = (double)sl.sim / 1e9, V = (double)sl.v_end / 1e9;
			computing += (double)(sl.v_end - sl.v_start);
			charged += (double)sl.charged;
			switch (kind) {
			case PlotKind::Timing:
				snprintf(line, sizeof line, "%.9f %.9f\n", S, V);
				break;
			case PlotKind::Disparity:
				snprintf(line, sizeof line, "%.9f %.6f\n", S, (double)(sl.v_end - sl.sim) / 1e6);
				break;
			default:
				if (charged <= 0)
					continue;
				snprintf(line, sizeof line, "%.9f %.6f\n", V, 100 * (computing - charged) / charged);
				break;
			}
			s.data += line;
		}
		if (!s.data.empty())
			out.push_back(std::move(s));
	}
	if (out.empty())
		return Error{ t.path + ": no controller slices to plot" };
	return out;
}

Status run_gnuplot(const std::string &script)
{
	// fork and exec (coordinatord's spawn.h shadows <spawn.h> here); a
	// close-on-exec pipe tells an exec failure from gnuplot's own.
	int ready[2];
	if (pipe2(ready, O_CLOEXEC) < 0)
		return errno_error("pipe");
	pid_t pid = fork();
	if (pid < 0)
		return errno_error("fork");
	if (pid == 0) {
		// gnuplot's chatter on stdout is not ours; its errors on stderr are.
		int null = open("/dev/null", O_WRONLY);
		if (null >= 0)
			dup2(null, 1);
		execlp("gnuplot", "gnuplot", script.c_str(), (char *)nullptr);
		int err = errno;
		(void)!write(ready[1], &err, sizeof err);
		_exit(127);
	}
	close(ready[1]);
	int err = 0;
	bool exec_failed = read(ready[0], &err, sizeof err) == (ssize_t)sizeof err;
	close(ready[0]);
	int st = 0;
	while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
	}
	if (exec_failed && err == ENOENT)
		return Error{ "gnuplot not found on PATH: install it (Debian: apt-get install gnuplot-nox)" };
	if (exec_failed)
		return errno_error("cannot run gnuplot", err);
	if (!WIFEXITED(st) || WEXITSTATUS(st) != 0)
		return Error{ "gnuplot failed (its message is above)" };
	return Ok{};
}

} // namespace

Status plot_trace(const TraceData &t, PlotKind kind, const std::string &out)
{
	std::string ext = out.size() > 4 ? out.substr(out.size() - 4) : "";
	std::string terminal;
	if (ext == ".png")
		terminal = "pngcairo size 1200,700 enhanced font 'sans,11'";
	else if (ext == ".svg")
		terminal = "svg size 1200,700 dynamic enhanced font 'sans,11'";
	else
		return Error{ out + ": unknown image type (name it .png or .svg)" };
	auto series = series_for(t, kind);
	if (!series)
		return series.error();
	TempDir dir;
	if (auto s = dir.create(); !s)
		return s;

	std::ostringstream gp;
	gp << "set terminal " << terminal << "\n"
	   << "set output " << quoted(out) << "\n"
	   << "set grid\nset key top left box opaque\n";
	std::string title = plain(t.path);
	switch (kind) {
	case PlotKind::Timing:
		gp << "set title " << quoted("Controller time against simulation time: " + title) << "\n"
		   << "set xlabel 'simulation time (s)'\nset ylabel 'controller virtual time (s)'\n";
		break;
	case PlotKind::Disparity:
		gp << "set title " << quoted("Instantaneous disparity (controller - simulation): " + title) << "\n"
		   << "set xlabel 'simulation time (s)'\nset ylabel 'disparity (ms)'\n";
		break;
	case PlotKind::Error:
		gp << "set title " << quoted("Aggregate relative timing error (virtual time while computing vs CPU charged): " + title) << "\n"
		   << "set xlabel 'controller virtual time (s)'\nset ylabel 'relative error (%)'\n";
		break;
	case PlotKind::Joints:
		gp << "set title " << quoted("Joint states: " + title) << "\n"
		   << "set xlabel 'virtual time (s)'\nset ylabel 'value (rad, rad/s, m, m/s)'\n";
		break;
	}
	std::string plot = "plot ";
	for (size_t i = 0; i < series->size(); i++) {
		std::string file = dir.file("series" + std::to_string(i) + ".dat");
		std::ofstream f(file);
		f << (*series)[i].data;
		if (!f.flush())
			return errno_error("cannot write " + file);
		bool points = kind == PlotKind::Disparity;
		plot += (i ? ", " : "") + quoted(file) + " using 1:2 with " + (points ? "points pt 7 ps 0.4" : "lines lw 1.5") +
			" title " + quoted(plain((*series)[i].title));
	}
	if (kind == PlotKind::Timing)
		plot += ", x with lines dt 2 lc rgb 'gray40' title 'simulation time'";
	gp << plot << "\nset output\n";
	std::string script = dir.file("plot.gp");
	std::ofstream sf(script);
	sf << gp.str();
	if (!sf.flush())
		return errno_error("cannot write " + script);
	sf.close();

	unlink(out.c_str()); // so that a stale image cannot pass for this one
	if (auto s = run_gnuplot(script); !s)
		return s;
	struct stat st;
	if (stat(out.c_str(), &st) != 0 || st.st_size == 0)
		return Error{ out + ": gnuplot made no image" };
	return Ok{};
}

} // namespace tcs
