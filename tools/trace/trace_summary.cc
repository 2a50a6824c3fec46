// summarize() and the two renderings of its figures.
#include "trace_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>

#include "cli_time.h"
#include "json.h"

namespace tcs {

namespace {

int64_t median(std::vector<int64_t> v)
{
	if (v.empty())
		return 0;
	auto mid = v.begin() + (std::ptrdiff_t)(v.size() / 2);
	std::nth_element(v.begin(), mid, v.end());
	return *mid;
}

ControllerSummary summarize_controller(const TraceData &t, const TraceController &c)
{
	ControllerSummary s;
	s.info = &c;
	int64_t first = -1, last = 0;
	std::vector<int64_t> overshoots;
	for (const auto &sl : t.slices) {
		if (sl.controller != c.id)
			continue;
		if (first < 0)
			first = sl.v_start;
		last = std::max(last, sl.v_end);
		s.charged_ns += sl.charged;
		s.cpu_ns += sl.cpu;
		s.computing_ns += sl.v_end - sl.v_start;
		if (sl.end == TraceSlice::End::Preempted) {
			s.preemptions++;
			overshoots.push_back(sl.overshoot);
		}
	}
	s.span_ns = first < 0 ? 0 : last - first;
	s.start_ns = std::max<int64_t>(first, 0);
	s.overshoot = spread_of(std::move(overshoots));

	std::vector<const TraceWait *> loop;
	for (const auto &w : t.waits)
		if (w.controller == c.id && w.deadline >= 0 && w.absolute)
			loop.push_back(&w);
	s.periodic = !loop.empty();
	if (!s.periodic)
		for (const auto &w : t.waits)
			if (w.controller == c.id && w.deadline >= 0 && w.kind != "spin") // (a spin's stop: not a wait)
				loop.push_back(&w);
	s.cycles = loop.size();
	std::vector<int64_t> periods, steps;
	for (size_t i = 0; i < loop.size(); i++) {
		if (loop[i]->missed())
			s.misses++;
		if (i == 0)
			continue;
		periods.push_back(loop[i]->v_end - loop[i - 1]->v_end);
		int64_t d = loop[i]->deadline - loop[i - 1]->deadline;
		if (d > 0)
			steps.push_back(d);
	}
	if (s.periodic)
		s.asked_period = median(std::move(steps));
	if (loop.size() >= 2 && loop.back()->v_end > loop.front()->v_end)
		s.rate_hz = (double)(loop.size() - 1) * 1e9 / (double)(loop.back()->v_end - loop.front()->v_end);
	s.period = spread_of(std::move(periods));
	for (const auto &cmd : t.commands)
		if (cmd.controller == c.id && cmd.malformed)
			s.malformed_commands++;
	return s;
}

std::string dur(int64_t ns)
{
	return format_duration(ns);
}

std::string spread_text(const Spread &s)
{
	if (!s.count)
		return "none";
	return "p50 " + dur(s.p50) + ", p99 " + dur(s.p99) + ", max " + dur(s.max);
}

void json_spread(std::string &o, const char *key, const Spread &s)
{
	char buf[256];
	snprintf(buf, sizeof buf, "\"%s\":{\"count\":%zu,\"min_ns\":%lld,\"p50_ns\":%lld,\"p99_ns\":%lld,\"max_ns\":%lld}",
		 key, s.count, (long long)s.min, (long long)s.p50, (long long)s.p99, (long long)s.max);
	o += buf;
}

void json_field(std::string &o, const char *key, double v)
{
	char buf[128];
	if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9e15)
		snprintf(buf, sizeof buf, "\"%s\":%.0f", key, v);
	else if (std::isfinite(v))
		snprintf(buf, sizeof buf, "\"%s\":%.9g", key, v);
	else
		snprintf(buf, sizeof buf, "\"%s\":null", key);
	o += buf;
}

// ",key":value for each, as json_field writes them.
void json_fields(std::string &o, std::initializer_list<std::pair<const char *, double>> fields)
{
	for (const auto &[key, v] : fields) {
		o += ',';
		json_field(o, key, v);
	}
}

} // namespace

Spread spread_of(std::vector<int64_t> v)
{
	Spread s;
	if (v.empty())
		return s;
	std::sort(v.begin(), v.end());
	s.count = v.size();
	s.min = v.front();
	s.max = v.back();
	// Nearest rank: the smallest value with at least p of them at or below it.
	auto rank = [&](double p) { return v[std::min(v.size() - 1, (size_t)std::ceil(p * (double)v.size()) - 1)]; };
	s.p50 = rank(0.50);
	s.p99 = rank(0.99);
	return s;
}

RunSummary summarize(const TraceData &t)
{
	RunSummary r;
	r.path = t.path;
	r.truncated = t.truncated;
	r.virtual_ns = t.virtual_ns();
	r.wall_ns = t.wall_ns();
	r.steps = t.steps.size();
	std::vector<int64_t> costs;
	costs.reserve(t.steps.size());
	for (const auto &s : t.steps)
		costs.push_back(s.wall_cost);
	r.step_cost = spread_of(std::move(costs));
	double err = 0, charged = 0, cpu = 0, real_charged = 0;
	for (const auto &c : t.controllers) {
		r.controllers.push_back(summarize_controller(t, c));
		const auto &s = r.controllers.back();
		err += std::fabs((double)(s.computing_ns - s.charged_ns));
		charged += (double)s.charged_ns;
		cpu += (double)s.cpu_ns;
		real_charged += (double)s.charged_ns / (c.cpu_scale > 0 ? c.cpu_scale : 1);
	}
	r.wires = t.wires;
	r.timing_error = charged > 0 ? err / charged : 0;
	r.uncharged = cpu > 0 ? std::max(0.0, cpu - real_charged) / cpu : 0;
	return r;
}

std::string summary_text(const RunSummary &r)
{
	std::string o = r.path + ": " + dur(r.virtual_ns) + " virtual in " + dur(r.wall_ns) + " wall";
	if (r.wall_ns > 0)
		o += format_number(" (%.3gx real time)", (double)r.virtual_ns / (double)r.wall_ns);
	if (!r.controllers.empty())
		o += ", " + r.controllers.front().info->mode + " mode";
	o += "\n";
	if (r.truncated)
		o += "  the trace was not closed (the run was killed): figures up to its last complete chunk\n";
	if (r.steps)
		o += "  world: " + std::to_string(r.steps) + " steps; wall cost per step min " + dur(r.step_cost.min) +
		     ", median " + dur(r.step_cost.p50) + ", max " + dur(r.step_cost.max) + "\n";
	o += "  timing error: " + format_number("%.3f %%", 100 * r.timing_error) + " (virtual time while computing against CPU charged)";
	o += "; CPU not charged (tcs's hooks): " + format_number("%.2f %%", 100 * r.uncharged) + "\n";
	if (!r.controllers.empty() && r.controllers.front().info->mode == "lockstep")
		o += "  (lockstep: computation took no virtual time, whatever CPU it used, but for spins' clock and\n"
		     "  empty reads)\n";
	for (const auto &c : r.controllers) {
		const TraceController &i = *c.info;
		o += "controller " + std::to_string(i.id) + ": " + i.name + " (pid " + std::to_string(i.pid) + ")";
		if (i.cpu_scale != 1)
			o += format_number(", CPU scale %g", i.cpu_scale);
		o += "\n";
		o += "  cycles: " + std::to_string(c.cycles) + (c.periodic ? " periodic waits" : " timed waits");
		if (c.rate_hz > 0)
			o += format_number(", %.1f Hz", c.rate_hz);
		if (c.periodic && c.asked_period > 0)
			o += "; asked period " + dur(c.asked_period) + format_number(" (%.1f Hz)", 1e9 / (double)c.asked_period);
		o += "\n  period: " + spread_text(c.period) + "\n";
		if (c.periodic)
			o += "  deadline misses: " + std::to_string(c.misses) +
			     (c.cycles ? format_number(" (%.1f %%)", 100.0 * (double)c.misses / (double)c.cycles) : "") + "\n";
		else if (c.cycles)
			o += "  deadline misses: none to count (paced by relative sleeps, it asked for no period)\n";
		o += "  preemptions: " + std::to_string(c.preemptions);
		if (c.preemptions)
			o += "; overshoot (real CPU beyond the budget) p50 " + dur(c.overshoot.p50) + ", p99 " +
			     dur(c.overshoot.p99);
		o += "\n  charged CPU: " + dur(c.charged_ns);
		if (c.span_ns > 0)
			o += format_number(" (%.1f %% of its virtual time)", 100.0 * (double)c.charged_ns / (double)c.span_ns);
		o += "\n";
		if (c.malformed_commands)
			o += "  malformed actuator records: " + std::to_string(c.malformed_commands) + "\n";
		if (c.periodic && c.cycles)
			o += c.misses ? "  verdict: MISSED " + std::to_string(c.misses) + " of " + std::to_string(c.cycles) +
						" deadlines\n"
				      : "  verdict: kept every deadline\n";
	}
	if (!r.wires.empty())
		o += "wires:\n";
	for (const TraceWire &w : r.wires) {
		auto busy = [&](int64_t ns) {
			return r.virtual_ns > 0 ? format_number("%.2f %%", 100.0 * (double)ns / (double)r.virtual_ns)
						: std::string("-");
		};
		const bool serial = w.kind == "serial", i2c = w.kind == "i2c";
		o += "  " + w.name + ": " + std::to_string(w.messages) +
		     (serial ? " runs of bytes" : i2c ? " transfers" : " frames") + ", " + std::to_string(w.bytes) +
		     " bytes; busy " + busy(w.busy_ns) + (serial ? " of the run to the devices, " + busy(w.busy_back_ns) +
							   " back"
							 : " of the run");
		if (w.refused)
			o += "; " + std::to_string(w.refused) + (i2c ? " failed" : " refused by a device");
		o += "\n";
	}
	return o;
}

std::string summary_json(const RunSummary &r)
{
	std::string o = "{\"path\":";
	json_append_string(o, r.path);
	o += r.truncated ? ",\"truncated\":true," : ",\"truncated\":false,";
	json_field(o, "virtual_ns", (double)r.virtual_ns);
	o += ',';
	json_field(o, "wall_ns", (double)r.wall_ns);
	o += ',';
	json_field(o, "real_time_factor", r.wall_ns > 0 ? (double)r.virtual_ns / (double)r.wall_ns : 0);
	o += ',';
	json_field(o, "steps", (double)r.steps);
	o += ',';
	json_spread(o, "step_wall_cost", r.step_cost);
	o += ',';
	json_field(o, "timing_error", r.timing_error);
	o += ',';
	json_field(o, "uncharged_cpu", r.uncharged);
	o += ",\"controllers\":[";
	for (size_t k = 0; k < r.controllers.size(); k++) {
		const auto &c = r.controllers[k];
		o += k ? ",{" : "{";
		json_field(o, "controller", c.info->id);
		o += ",\"name\":";
		json_append_string(o, c.info->name);
		o += ",\"mode\":";
		json_append_string(o, c.info->mode);
		o += ',';
		json_field(o, "pid", (double)c.info->pid);
		o += ',';
		json_field(o, "cpu_scale", c.info->cpu_scale);
		o += c.periodic ? ",\"periodic\":true," : ",\"periodic\":false,";
		json_field(o, "cycles", (double)c.cycles);
		o += ',';
		json_field(o, "rate_hz", c.rate_hz);
		o += ',';
		json_field(o, "asked_period_ns", (double)c.asked_period);
		o += ',';
		json_spread(o, "period", c.period);
		o += ',';
		json_field(o, "deadline_misses", (double)c.misses);
		o += ',';
		json_field(o, "preemptions", (double)c.preemptions);
		o += ',';
		json_spread(o, "overshoot", c.overshoot);
		json_fields(o, { { "charged_cpu_ns", (double)c.charged_ns },
				 { "used_cpu_ns", (double)c.cpu_ns },
				 { "span_ns", (double)c.span_ns },
				 { "start_ns", (double)c.start_ns },
				 { "malformed_commands", (double)c.malformed_commands } });
		o += '}';
	}
	o += "],\"wires\":[";
	for (size_t k = 0; k < r.wires.size(); k++) {
		const TraceWire &w = r.wires[k];
		o += k ? ",{\"topic\":" : "{\"topic\":";
		json_append_string(o, w.topic);
		o += ",\"kind\":";
		json_append_string(o, w.kind);
		o += ",\"name\":";
		json_append_string(o, w.name);
		json_fields(o, { { "messages", (double)w.messages },
				 { "bytes", (double)w.bytes },
				 { "busy_ns", (double)w.busy_ns },
				 { "busy_back_ns", (double)w.busy_back_ns },
				 { "refused", (double)w.refused } });
		o += '}';
	}
	o += "]}\n";
	return o;
}

} // namespace tcs
