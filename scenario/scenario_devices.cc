// Reading the [[device]] tables of a scenario (see scenario_devices.h).
#include "scenario_devices.h"

#include <utility>

#include "scenario_units.h"
#include "toml_text_shift.h"

namespace tcs::scenario_parse {

namespace {

Status parse_signals(ScenarioReader &r, const Entry &e, DeviceSpec *d)
{
	const toml::array *a = e.node->as_array();
	if (!a)
		return r.err(e.line, "signals must be an array of strings such as [\"pendulum.hinge.position\"], "
				   "not " + std::string(type_name(*e.node)));
	if (a->empty())
		return r.err(e.line, "signals is empty: a device carries at least one signal");
	bool actuator = d->kind == DeviceSpec::Kind::Actuator;
	for (const toml::node &n : *a) {
		int line = line_of(n);
		if (!n.is_string())
			return r.err(line, "signals must be strings, not " + std::string(type_name(n)));
		const std::string name = unshift(n.as_string()->get());
		auto parts = r.signal_parts(line, name);
		if (!parts)
			return parts.error();
		if (actuator && parts->field != "effort")
			return r.err(line, "actuator signal '" + name + "' is not an effort: actuators drive "
									"<model>.<joint>.effort");
		for (const SignalRef &s : d->signals)
			if (s.name == name)
				return r.err(line, "signal '" + name + "' is listed twice");
		if (actuator)
			for (const DeviceSpec &o : r.sc.devices)
				if (o.kind == DeviceSpec::Kind::Actuator)
					for (const SignalRef &s : o.signals)
						if (s.name == name)
							return r.err(line, "signal '" + name + "' is already driven by " +
										 o.path + " (line " +
										 std::to_string(s.line) + ")");
		d->signals.push_back({ name, line });
	}
	return Ok{};
}

Status parse_device(ScenarioReader &r, const toml::table &t)
{
	using D = DeviceSpec;
	D d;
	d.line = line_of(t);
	if (Status s = r.check_keys(t, "in [[device]]",
				  { "path", "kind", "signals", "format", "mode", "rate", "limit" });
	    !s)
		return s;
	auto es = entries(t);
	const Entry *kind = find_entry(es, "kind");
	const Entry *path = find_entry(es, "path");
	const Entry *signals = find_entry(es, "signals");
	for (auto [entry, key] : { std::pair{ kind, "kind" }, { path, "path" }, { signals, "signals" } })
		if (!entry)
			return r.err(d.line, std::string("[[device]] needs '") + key + "'");

	auto k = r.get_string(*kind, "\"sensor\"");
	if (!k)
		return k.error();
	if (*k != "sensor" && *k != "actuator")
		return r.err(kind->line, "kind must be \"sensor\" or \"actuator\", not \"" + *k + "\"");
	d.kind = *k == "sensor" ? D::Kind::Sensor : D::Kind::Actuator;
	bool sensor = d.kind == D::Kind::Sensor;

	auto p = r.get_string(*path, "\"/dev/tcs/pendulum/state\"");
	if (!p)
		return p.error();
	if (!is_normal_absolute_path(*p))
		return r.err(path->line, "device path '" + *p + "' must be absolute and normal (no '.', '..', "
									"'//' or trailing '/')");
	for (const D &other : r.sc.devices)
		if (other.path == *p)
			return r.err(path->line, "device path '" + *p + "' is already used at line " +
							std::to_string(other.line));
	d.path = *p;

	if (Status s = parse_signals(r, *signals, &d); !s)
		return s;

	if (const Entry *f = find_entry(es, "format")) {
		auto v = r.get_string(*f, "\"text\"");
		if (!v)
			return v.error();
		if (*v != "text" && *v != "binary")
			return r.err(f->line, "format must be \"text\" or \"binary\", not \"" + *v + "\"");
		d.format = *v == "text" ? D::Format::Text : D::Format::Binary;
	}

	const Entry *mode = find_entry(es, "mode");
	const Entry *rate = find_entry(es, "rate");
	const Entry *limit = find_entry(es, "limit");
	if (sensor && limit)
		return r.err(limit->line, "'limit' applies to actuators only, not to a sensor");
	if (!sensor && (mode || rate))
		return r.err((mode ? mode : rate)->line,
			   "'" + (mode ? mode : rate)->key +
				   "' applies to sensors only: an actuator takes each command as it is written");
	if (mode) {
		auto v = r.get_string(*mode, "\"stream\"");
		if (!v)
			return v.error();
		if (*v != "stream" && *v != "latest")
			return r.err(mode->line, "mode must be \"stream\" or \"latest\", not \"" + *v + "\"");
		d.mode = *v == "stream" ? D::Mode::Stream : D::Mode::Latest;
	}
	if (sensor && d.mode == D::Mode::Latest && rate)
		return r.err(rate->line, "'rate' applies only to mode = \"stream\": a \"latest\" sensor "
				       "answers every read with the current value");
	if (sensor && d.mode == D::Mode::Stream) {
		if (!rate)
			return r.err(d.line, "a stream sensor needs a rate, such as rate = \"1kHz\"");
		auto text = r.get_string(*rate, "\"1kHz\"");
		if (!text)
			return text.error();
		auto hz = parse_rate_hz(*text);
		if (!hz)
			return r.err(rate->line, "rate: " + hz.error().message);
		d.rate_hz = *hz;
		d.period_ns = rate_period_ns(*hz);
	}
	if (limit) {
		auto v = r.get_number(*limit, "limit");
		if (!v)
			return v.error();
		if (*v <= 0)
			return r.err(limit->line, "limit must be positive (it bounds the command's magnitude)");
		d.limit = *v;
	}
	r.sc.devices.push_back(std::move(d));
	return Ok{};
}

} // namespace

Status parse_devices(const toml::table &root, ScenarioReader &r)
{
	auto tables = r.table_array(root, "device");
	if (!tables)
		return tables.error();
	for (const toml::table *t : *tables)
		if (Status s = parse_device(r, *t); !s)
			return s;
	return Ok{};
}

} // namespace tcs::scenario_parse
