// Formatting of progress, summary and exit status.
#include "run_report.h"

#include <signal.h>
#include <string.h>
#include <sys/wait.h>

#include <cstdio>

#include "cli_time.h"

namespace tcs {

namespace {

std::string speed(int64_t virtual_ns, int64_t wall_ns)
{
	if (wall_ns <= 0)
		return "";
	double x = (double)virtual_ns / (double)wall_ns;
	return format_number(x >= 100 ? "%.0fx real time" : x >= 10 ? "%.1fx real time" : "%.3gx real time", x);
}

std::string how_it_ended(const ControllerReport &c)
{
	if (!c.dropped.empty())
		return "dropped by tcs: " + c.dropped;
	if (c.ended_by_tcs)
		return "ended with the run";
	int st = c.wait_status;
	if (st < 0)
		return "still running";
	if (WIFEXITED(st))
		return "exited " + std::to_string(WEXITSTATUS(st));
	if (WIFSIGNALED(st))
		return std::string("killed by SIG") + (sigabbrev_np(WTERMSIG(st)) ? sigabbrev_np(WTERMSIG(st)) : "?") +
		       (WCOREDUMP(st) ? " (core dumped)" : "");
	return "ended";
}

} // namespace

int status_code(int st)
{
	if (WIFEXITED(st))
		return WEXITSTATUS(st);
	if (WIFSIGNALED(st))
		return 128 + WTERMSIG(st);
	return 0;
}

std::string progress_line(int64_t virtual_ns, int64_t wall_ns)
{
	return "tcs-run: " + format_duration(virtual_ns) + " virtual, " + format_duration(wall_ns) + " wall, " +
	       speed(virtual_ns, wall_ns);
}

std::string summary(const RunReport &r, int mode, const std::string &who)
{
	std::string s = who + ": " + format_duration(r.virtual_ns) + " virtual in " + format_duration(r.wall_ns) +
			" wall (" + speed(r.virtual_ns, r.wall_ns) + "), " +
			(mode == TCS_MODE_LOCKSTEP ? "lockstep" : "cpu") + " mode, ";
	s += r.realtime.fifo ? "SCHED_FIFO" : "normal scheduling";
	// tcs's own core first; controllers run on all of them, one on each.
	if (r.realtime.cores.size() > 1) {
		s += " on CPUs ";
		for (size_t i = 0; i < r.realtime.cores.size(); i++)
			s += (i ? "," : "") + std::to_string(r.realtime.cores[i]);
	} else if (r.realtime.cpu >= 0) {
		s += " on CPU " + std::to_string(r.realtime.cpu);
	}
	// What the kernel charges a stopped controller, left out (stop_cost.h).
	const StopCost &stop = r.stop_costs.other;
	if (mode == TCS_MODE_CPU && stop.stop_ns + stop.continue_ns > 0)
		s += "; a stop costs " + format_duration(stop.stop_ns + stop.continue_ns) + " of CPU, not charged";
	s += "\n";
	if (r.step_wall_max > 0)
		s += who + ":   world: " + std::to_string(r.steps) + " steps; wall cost per step min " +
		     format_duration(r.step_wall_min) + ", median " + format_duration(r.step_wall_median) + ", max " +
		     format_duration(r.step_wall_max) + "\n";
	// Child processes of the controllers: one line for them all.
	size_t children = 0;
	int64_t children_cpu = 0;
	for (const auto &c : r.controllers)
		if (c.child) {
			children++;
			children_cpu += c.charged_ns;
		}
	for (const auto &c : r.controllers) {
		if (c.child)
			continue;
		s += who + ":   " + c.name + " (pid " + std::to_string(c.pid) + "): " + how_it_ended(c);
		uint64_t cycles = c.periodic_waits ? c.periodic_waits : c.waits;
		double secs = (double)c.virtual_ns / 1e9;
		s += "; " + std::to_string(cycles) + (c.periodic_waits ? " periodic" : "") + " waits";
		if (secs > 0 && cycles > 0)
			s += format_number(" (%.1f Hz)", (double)cycles / secs);
		if (c.periodic_waits)
			s += ", " + std::to_string(c.deadline_misses) + " deadline misses";
		if (c.spin_stops)
			s += "; " + std::to_string(c.spin_stops) + (c.spin_stops == 1 ? " spin stop" : " spin stops") +
			     " (lockstep: see --spin-cost)";
		s += "; CPU " + format_duration(c.charged_ns);
		if (c.virtual_ns > 0)
			s += format_number(" (%.1f %%)", 100.0 * (double)c.charged_ns / (double)c.virtual_ns);
		if (!c.attached && c.dropped.empty())
			s += "; never loaded libtcs_preload";
		s += "\n";
	}
	if (children)
		s += who + ":   and " + std::to_string(children) + (children == 1 ? " child process" : " child processes") +
		     " of theirs, each in virtual time on a CPU of its own; CPU " + format_duration(children_cpu) + "\n";
	return s;
}

std::string drops(const RunReport &r, const std::string &who)
{
	std::string s;
	for (const auto &c : r.controllers)
		if (!c.dropped.empty())
			s += who + ": error: " + c.name + " (pid " + std::to_string(c.pid) + ") dropped by tcs: " + c.dropped + "\n";
	return s;
}

int exit_status(const RunReport &r)
{
	for (const auto &c : r.controllers)
		if (!c.dropped.empty())
			return 2;
	if (r.reason == EndReason::Signal)
		return 128 + r.signal;
	if (r.reason == EndReason::Lost)
		return 2;
	for (const auto &c : r.controllers)
		if (!c.child && !c.ended_by_tcs && c.wait_status >= 0 && status_code(c.wait_status) != 0)
			return status_code(c.wait_status);
	return 0;
}

} // namespace tcs
