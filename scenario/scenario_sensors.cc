// Reading the [[sensor]] tables of a scenario (see scenario_sensors.h).
#include "scenario_sensors.h"

#include <cmath>

#include "scenario_units.h"
#include "toml_text_shift.h"

namespace tcs::scenario_parse {

namespace {

// A read older than this is no sensor's latency but a mistake (and each
// signal keeps that much history).
constexpr int64_t kMaxLatencyNs = 10 * 1000000000LL;

Result<double> number_at_least(ScenarioReader &r, const Entry &e, double least, bool strict, const char *why)
{
	auto v = r.get_number(e, e.key);
	if (!v)
		return v.error();
	if (!std::isfinite(*v) || *v < least || (strict && *v == least))
		return r.err(e.line, e.key + " must be " + why);
	return *v;
}

Status parse_sensor(ScenarioReader &r, const toml::table &t)
{
	SensorModelSpec sm;
	sm.line = line_of(t);
	if (Status s = r.check_keys(t, "in [[sensor]]", { "signal", "noise", "bias", "resolution", "latency", "rate" }); !s)
		return s;
	auto es = entries(t);
	const Entry *signal = find_entry(es, "signal");
	if (!signal)
		return r.err(sm.line, "[[sensor]] needs a signal, such as signal = \"arm.joint1.position\"");
	auto name = r.get_string(*signal, "\"arm.joint1.position\"");
	if (!name)
		return name.error();
	*name = unshift(*name);
	auto parts = r.signal_parts(signal->line, *name);
	if (!parts)
		return parts.error();
	for (const SensorModelSpec &o : r.sc.sensors)
		if (o.signal.name == *name)
			return r.err(signal->line, "signal '" + *name + "' already has a sensor model (line " +
							   std::to_string(o.line) + ")");
	sm.signal = { *name, signal->line };
	if (const Entry *e = find_entry(es, "noise")) {
		auto v = number_at_least(r, *e, 0, false, "a standard deviation >= 0, in the signal's unit");
		if (!v)
			return v.error();
		sm.noise = *v;
	}
	if (const Entry *e = find_entry(es, "bias")) {
		auto v = number_at_least(r, *e, -HUGE_VAL, false, "a finite number, in the signal's unit");
		if (!v)
			return v.error();
		sm.bias = *v;
	}
	if (const Entry *e = find_entry(es, "resolution")) {
		auto v = number_at_least(r, *e, 0, true, "a quantisation step > 0, in the signal's unit");
		if (!v)
			return v.error();
		sm.resolution = *v;
	}
	if (const Entry *e = find_entry(es, "latency")) {
		auto text = r.get_string(*e, "\"2ms\"");
		if (!text)
			return text.error();
		auto ns = parse_duration_ns(*text);
		if (!ns)
			return r.err(e->line, "latency: " + ns.error().message);
		if (*ns > kMaxLatencyNs)
			return r.err(e->line, "latency '" + *text + "' is more than 10 s");
		sm.latency_ns = *ns;
	}
	if (const Entry *e = find_entry(es, "rate")) {
		auto text = r.get_string(*e, "\"100Hz\"");
		if (!text)
			return text.error();
		auto hz = parse_rate_hz(*text);
		if (!hz)
			return r.err(e->line, "rate: " + hz.error().message);
		sm.rate_hz = *hz;
	}
	r.sc.sensors.push_back(std::move(sm));
	return Ok{};
}

} // namespace

Status parse_sensors(const toml::table &root, ScenarioReader &r)
{
	auto tables = r.table_array(root, "sensor");
	if (!tables)
		return tables.error();
	for (const toml::table *t : *tables)
		if (Status s = parse_sensor(r, *t); !s)
			return s;
	return Ok{};
}

} // namespace tcs::scenario_parse
