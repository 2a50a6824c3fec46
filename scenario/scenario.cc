// Reading a scenario file: TOML in, a checked Scenario out, or the first
// problem as "FILE:LINE: what is wrong". Problems are looked for in a fixed
// order (syntax, then [sim], models, devices, sensor models, CAN buses,
// serial lines, I2C buses, controllers; within a table unknown keys first,
// in file order), so the same file always gives the same message. The
// sections' parsers are scenario_models.cc, scenario_devices.cc,
// scenario_sensors.cc, scenario_can.cc, scenario_serial.cc and
// scenario_i2c.cc; the controllers, short, are here, and so is the check
// of every name against the world's signals.
#include "scenario.h"

#include <algorithm>
#include <unordered_set>

#include "read_file.h"
#include "scenario_can.h"
#include "scenario_devices.h"
#include "scenario_i2c.h"
#include "scenario_models.h"
#include "scenario_reader.h"
#include "scenario_sensors.h"
#include "scenario_serial.h"
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
	Status s = r.check_keys(root, "at the top level",
				{ "sim", "model", "device", "sensor", "can", "serial", "i2c", "controller" });
	if (s)
		s = parse_sim(root, r);
	if (s)
		s = parse_models(root, r);
	if (s)
		s = parse_devices(root, r);
	if (s)
		s = parse_sensors(root, r);
	if (s)
		s = parse_cans(root, r);
	if (s)
		s = parse_serials(root, r);
	if (s)
		s = parse_i2cs(root, r);
	if (s)
		s = parse_controllers(root, r);
	if (!s)
		return s.error();
	return std::move(r.sc);
}

// What the world's signal list must hold for one name of the scenario: a
// signal (a frame field's without its index), a joint's three, a link's two.
struct Need {
	enum Kind { Signal, Joint, Link } kind;
	const SignalRef *ref;
	std::vector<std::string> signals;
};

Need signal_need(const SignalRef &s)
{
	auto ix = split_signal_index(s.name);
	return { Need::Signal, &s, { ix ? std::string(ix->signal) : s.name } };
}

std::vector<std::string> part_signals(const std::string &name, Need::Kind kind)
{
	if (kind == Need::Joint)
		return { name + ".position", name + ".velocity", name + ".effort" };
	return { name + ".pose", name + ".twist" };
}

Need part_need(const SignalRef &s, Need::Kind kind)
{
	return { kind, &s, part_signals(s.name, kind) };
}

bool ends_with(std::string_view s, std::string_view tail)
{
	return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

// What `model` has of a kind, for a message: its signals, or its joints (a
// position, velocity and effort) or links (a pose and twist), in the
// world's order.
std::vector<std::string> model_has(const std::unordered_set<std::string_view> &set, const std::vector<std::string> &known,
				   const std::string &model, Need::Kind kind)
{
	std::vector<std::string> theirs;
	for (const std::string &k : known) {
		if (k.size() <= model.size() || k.compare(0, model.size(), model) != 0 || k[model.size()] != '.')
			continue;
		if (kind == Need::Signal) {
			theirs.push_back(k);
			continue;
		}
		const std::string_view first = kind == Need::Joint ? ".position" : ".pose";
		if (!ends_with(k, first))
			continue;
		std::string stem = k.substr(0, k.size() - first.size());
		const std::vector<std::string> signals = part_signals(stem, kind);
		if (std::all_of(signals.begin(), signals.end(), [&](const std::string &x) { return set.count(x); }))
			theirs.push_back(stem);
	}
	return theirs;
}

} // namespace

Error scenario_error(const Scenario &scenario, int line, const std::string &what)
{
	return Error{ scenario.file + ":" + std::to_string(line) + ": " + what };
}

Status check_signals(const Scenario &scenario, const std::vector<std::string> &known)
{
	std::unordered_set<std::string_view> set(known.begin(), known.end());
	std::vector<Need> needs;
	for (const DeviceSpec &d : scenario.devices)
		for (const SignalRef &s : d.signals)
			needs.push_back(signal_need(s));
	for (const SensorModelSpec &sm : scenario.sensors)
		needs.push_back(signal_need(sm.signal));
	for (const CanSpec &c : scenario.cans) {
		for (const CanMotorSpec &m : c.motors)
			needs.push_back(part_need(m.joint, Need::Joint));
		for (const CanFrameSpec &f : c.frames)
			for (const CanFieldSpec &field : f.fields)
				needs.push_back(signal_need(field.signal));
	}
	for (const SerialSpec &s : scenario.serials)
		for (const ServoSpec &v : s.servos)
			needs.push_back(part_need(v.joint, Need::Joint));
	for (const I2cSpec &b : scenario.i2cs)
		for (const I2cDeviceSpec &d : b.devices)
			needs.push_back(part_need(d.link, Need::Link));
	// The first in the file is the one reported, whatever its table.
	std::stable_sort(needs.begin(), needs.end(), [](const Need &a, const Need &b) { return a.ref->line < b.ref->line; });
	for (const Need &n : needs) {
		if (std::all_of(n.signals.begin(), n.signals.end(), [&](const std::string &x) { return set.count(x); }))
			continue;
		const std::string &name = n.ref->name;
		std::string model = name.substr(0, name.find('.'));
		std::vector<std::string> theirs = model_has(set, known, model, n.kind);
		static const char *const kinds[] = { "signal", "joint", "link" };
		const std::string kind = kinds[n.kind];
		return scenario_error(scenario, n.ref->line,
				      "unknown " + kind + " '" + name + "' (model '" + model +
					      (theirs.empty() ? "' has no " + kind + "s)" : "' has: " + join(theirs) + ")"));
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
