// Reading a scenario file: TOML in, a checked Scenario out, or the first
// problem as "FILE:LINE: what is wrong". Problems are looked for in a fixed
// order (syntax, then [sim], models, devices, controllers; within a table
// unknown keys first, in file order), so the same file always gives the
// same message. The sections' parsers are scenario_models.cc and
// scenario_devices.cc; the controllers, short, are here.
#include "scenario.h"

#include <unordered_set>

#include "read_file.h"
#include "scenario_devices.h"
#include "scenario_models.h"
#include "scenario_reader.h"
#include "scenario_sensors.h"
#include "scenario_units.h"
#include "toml_text_shift.h"

namespace tcs {

using namespace scenario_parse;

namespace {

// Enough for any hand-written world; a bigger file is a mistake (a mesh
// passed for a scenario), not something to load into memory.
constexpr size_t kMaxScenarioBytes = 4u << 20;

Status parse_controllers(const toml::table &root, ScenarioReader &r)
{
	auto tables = r.table_array(root, "controller");
	if (!tables)
		return tables.error();
	for (const toml::table *t : *tables) {
		ControllerEntry c;
		c.line = line_of(*t);
		if (Status s = r.check_keys(*t, "in [[controller]]", { "command", "cpu_scale" }); !s)
			return s;
		auto es = entries(*t);
		const Entry *command = find_entry(es, "command");
		if (!command)
			return r.err(c.line, "[[controller]] needs a command");
		auto text = r.get_string(*command, "\"examples/pendulum_pd --rate 1000\"");
		if (!text)
			return text.error();
		auto argv = split_command(*text);
		if (!argv)
			return r.err(command->line, "command: " + argv.error().message);
		if (argv->empty())
			return r.err(command->line, "command is empty");
		c.command = *text;
		c.argv = std::move(*argv);
		if (const Entry *scale = find_entry(es, "cpu_scale")) {
			auto v = r.get_number(*scale, "cpu_scale");
			if (!v)
				return v.error();
			if (*v <= 0 || *v > 1e6)
				return r.err(scale->line, "cpu_scale must be positive (virtual seconds per CPU "
							"second, at most 1e6)");
			c.cpu_scale = *v;
		}
		r.sc.controllers.push_back(std::move(c));
	}
	return Ok{};
}

// The sections in their fixed order.
Result<Scenario> parse(ScenarioReader &r, std::string_view text)
{
	int bad_line = 0;
	auto shifted_text = shift_for_toml(text, &bad_line);
	if (!shifted_text)
		return r.err(bad_line, "characters U+F0080 to U+FFEFE (private use) cannot be used");
	toml::parse_result parsed = toml::parse(*shifted_text, r.sc.file);
	if (!parsed)
		return r.err((int)parsed.error().source().begin.line, unshift(parsed.error().description()));
	const toml::table &root = parsed.table();
	Status s = r.check_keys(root, "at the top level", { "sim", "model", "device", "sensor", "controller" });
	if (s)
		s = parse_sim(root, r);
	if (s)
		s = parse_models(root, r);
	if (s)
		s = parse_devices(root, r);
	if (s)
		s = parse_sensors(root, r);
	if (s)
		s = parse_controllers(root, r);
	if (!s)
		return s.error();
	return std::move(r.sc);
}

} // namespace

Error scenario_error(const Scenario &scenario, int line, const std::string &what)
{
	return Error{ scenario.file + ":" + std::to_string(line) + ": " + what };
}

Status check_signals(const Scenario &scenario, const std::vector<std::string> &known)
{
	std::unordered_set<std::string_view> set(known.begin(), known.end());
	std::vector<const SignalRef *> refs;
	for (const DeviceSpec &d : scenario.devices)
		for (const SignalRef &s : d.signals)
			refs.push_back(&s);
	for (const SensorModelSpec &sm : scenario.sensors)
		refs.push_back(&sm.signal);
	for (const SignalRef *s : refs) {
		if (set.count(s->name))
			continue;
		std::string model = s->name.substr(0, s->name.find('.'));
		std::vector<std::string> theirs;
		for (const std::string &k : known)
			if (k.size() > model.size() && k.compare(0, model.size(), model) == 0 && k[model.size()] == '.')
				theirs.push_back(k);
		return scenario_error(scenario, s->line,
				      "unknown signal '" + s->name + "' (model '" + model +
					      (theirs.empty() ? "' has no signals)" : "' has: " + join(theirs) + ")"));
	}
	return Ok{};
}

Result<Scenario> parse_scenario_text(const std::string &text, const std::string &name_for_errors)
{
	ScenarioReader r(name_for_errors, "");
	return parse(r, text);
}

Result<Scenario> parse_scenario_file(const std::string &path)
{
	auto text = read_file(path, kMaxScenarioBytes);
	if (!text)
		return text.error();
	size_t slash = path.rfind('/');
	std::string dir = slash == std::string::npos ? "" : path.substr(0, slash == 0 ? 1 : slash);
	ScenarioReader r(path, dir);
	return parse(r, *text);
}

} // namespace tcs
