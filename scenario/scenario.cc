// Reading a scenario file: TOML in, a checked Scenario out, or the first
// problem as "FILE:LINE: what is wrong". Problems are looked for in a fixed
// order (syntax, then [sim], models, devices, controllers; within a table
// unknown keys first, in file order), so the same file always gives the
// same message.

// toml++ reports errors as values only when built without exceptions; it
// is used header-only for that reason (Debian's shared build throws), and
// only in this file. Its assertions are preconditions that 3.3 breaks on
// malformed input ("[=x]", "[1, }": upstream PR 301) where the code after
// them reports the error properly: off, as in any GCC release build.
#define TOML_EXCEPTIONS 0
#define TOML_ASSERT(expr) static_assert(true)
#include <toml++/toml.h>

#include "scenario.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <initializer_list>
#include <map>
#include <unordered_set>

#include "scenario_units.h"
#include "read_file.h"
#include "toml_text_shift.h"

namespace tcs {

namespace {

// Enough for any hand-written world; a bigger file is a mistake (a mesh
// passed for a scenario), not something to load into memory.
constexpr size_t kMaxScenarioBytes = 4u << 20;
constexpr int64_t kMinStepNs = 10000;      // 10 us
constexpr int64_t kMaxStepNs = 1000000000; // 1 s

int line_of(const toml::node &n)
{
	return (int)n.source().begin.line;
}

const char *type_name(const toml::node &n)
{
	switch (n.type()) {
	case toml::node_type::table:
		return "a table";
	case toml::node_type::array:
		return "an array";
	case toml::node_type::string:
		return "a string";
	case toml::node_type::integer:
		return "an integer";
	case toml::node_type::floating_point:
		return "a float";
	case toml::node_type::boolean:
		return "a boolean";
	default:
		return "a date or time";
	}
}

bool ends_with(std::string_view s, std::string_view tail)
{
	return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

bool is_model_path(std::string_view type)
{
	return type.find('/') != std::string_view::npos || ends_with(type, ".sdf") || ends_with(type, ".urdf");
}

// Absolute, and spelled one way only, so that comparing strings finds
// every duplicate.
bool is_normal_absolute(std::string_view p)
{
	if (p.size() < 2 || p[0] != '/' || p.back() == '/')
		return false;
	size_t i = 1;
	while (i <= p.size()) {
		size_t j = p.find('/', i);
		if (j == std::string_view::npos)
			j = p.size();
		std::string_view part = p.substr(i, j - i);
		if (part.empty() || part == "." || part == "..")
			return false;
		i = j + 1;
	}
	return p.find('\0') == std::string_view::npos;
}

std::string join(const std::vector<std::string> &v)
{
	std::string s;
	for (const auto &x : v)
		s += (s.empty() ? "" : ", ") + x;
	return s;
}


struct Entry {
	int line;
	std::string key;
	const toml::node *node;
};

// A table's entries in file order (toml++ keeps them sorted by key).
std::vector<Entry> entries(const toml::table &t)
{
	std::vector<Entry> v;
	for (auto &&[k, n] : t) {
		int line = (int)k.source().begin.line;
		v.push_back({ line ? line : line_of(n), unshift(k.str()), &n });
	}
	std::stable_sort(v.begin(), v.end(), [](const Entry &a, const Entry &b) { return a.line < b.line; });
	return v;
}

// One key of t, if there.
std::optional<Entry> lookup(const toml::table &t, std::string_view key)
{
	auto it = t.find(key);
	if (it == t.end())
		return std::nullopt;
	int line = (int)it->first.source().begin.line;
	return Entry{ line ? line : line_of(it->second), std::string(key), &it->second };
}

class Parser {
public:
	Parser(std::string file, std::string dir) : dir_(std::move(dir)) { sc_.file = std::move(file); }

	Result<Scenario> run(std::string_view text)
	{
		int bad_line = 0;
		auto shifted_text = shift_for_toml(text, &bad_line);
		if (!shifted_text)
			return err(bad_line, "characters U+F0080 to U+FFEFE (private use) cannot be used");
		toml::parse_result r = toml::parse(*shifted_text, sc_.file);
		if (!r)
			return err((int)r.error().source().begin.line, unshift(r.error().description()));
		const toml::table &root = r.table();
		Status s = check_keys(root, "at the top level", { "sim", "model", "device", "controller" });
		if (s)
			s = parse_sim(root);
		if (s)
			s = parse_models(root);
		if (s)
			s = parse_devices(root);
		if (s)
			s = parse_controllers(root);
		if (!s)
			return s.error();
		return std::move(sc_);
	}

private:
	Error err(int line, const std::string &what) { return scenario_error(sc_, line, what); }

	Status check_keys(const toml::table &t, const std::string &where, std::initializer_list<const char *> known)
	{
		for (const Entry &e : entries(t)) {
			if (std::find(known.begin(), known.end(), e.key) != known.end())
				continue;
			std::string list;
			for (const char *k : known)
				list += (list.empty() ? "" : ", ") + std::string(k);
			return err(e.line, "unknown key '" + e.key + "' " + where + " (known: " + list + ")");
		}
		return Ok{};
	}

	// The key's entry, or nullptr.
	static const Entry *find(const std::vector<Entry> &es, std::string_view key)
	{
		for (const Entry &e : es)
			if (e.key == key)
				return &e;
		return nullptr;
	}

	Result<std::string> get_string(const Entry &e, const std::string &example)
	{
		if (!e.node->is_string())
			return err(e.line, e.key + " must be a string such as " + example + ", not " + type_name(*e.node));
		return unshift(e.node->as_string()->get());
	}

	Result<double> get_number(const Entry &e, const std::string &what)
	{
		std::optional<double> v;
		if (e.node->is_integer())
			v = (double)e.node->as_integer()->get();
		else if (e.node->is_floating_point())
			v = e.node->as_floating_point()->get();
		if (!v)
			return err(e.line, what + " must be a number, not " + type_name(*e.node));
		if (!std::isfinite(*v))
			return err(e.line, what + " must be a finite number");
		return *v;
	}

	// An array of tables under `key`, written [[key]]; empty if absent.
	Result<std::vector<const toml::table *>> table_array(const toml::table &root, const char *key)
	{
		std::vector<const toml::table *> out;
		std::optional<Entry> e = lookup(root, key);
		if (!e)
			return out;
		const toml::array *a = e->node->as_array();
		if (!a || (!a->empty() && !a->is_array_of_tables()))
			return err(e->line, std::string("'") + key + "' must be written [[" + key + "]] (an array of tables)");
		for (const toml::node &n : *a)
			out.push_back(n.as_table());
		return out;
	}

	Status parse_sim(const toml::table &root)
	{
		std::optional<Entry> e = lookup(root, "sim");
		if (!e)
			return Ok{};
		const toml::table *t = e->node->as_table();
		if (!t)
			return err(e->line, "'sim' must be a table ([sim]), not " + std::string(type_name(*e->node)));
		sc_.sim.line = line_of(*t);
		if (Status s = check_keys(*t, "in [sim]", { "step", "model" }); !s)
			return s;
		auto es = entries(*t);
		if (const Entry *step = find(es, "step")) {
			sc_.sim.line = step->line;
			auto text = get_string(*step, "\"1ms\"");
			if (!text)
				return text.error();
			auto ns = parse_duration_ns(*text);
			if (!ns)
				return err(step->line, "step: " + ns.error().message);
			if (*ns < kMinStepNs || *ns > kMaxStepNs)
				return err(step->line, "step '" + *text + "' is out of range (10us to 1s)");
			sc_.sim.step_ns = *ns;
		}
		if (const Entry *model = find(es, "model")) {
			auto type = get_string(*model, "\"pendulum\"");
			if (!type)
				return type.error();
			if (type->empty())
				return err(model->line, "model is empty (built-in: pendulum, cartpole, double_pendulum, "
							"boxes; or a .sdf/.urdf path)");
			sim_model_ = ModelSpec{ "", *type, {}, model->line };
		}
		return Ok{};
	}

	std::string resolve_type(const std::string &type) const
	{
		if (!is_model_path(type) || type[0] == '/' || dir_.empty())
			return type;
		return dir_ + (dir_.back() == '/' ? "" : "/") + type;
	}

	// A model's numeric parameters: every key of t but those in `skip`.
	Status parse_params(const toml::table &t, ModelSpec *m, std::initializer_list<const char *> skip)
	{
		for (const Entry &e : entries(t)) {
			if (std::find(skip.begin(), skip.end(), e.key) != skip.end())
				continue;
			if ((e.key == "name" || e.key == "type") && !e.node->is_number())
				return err(e.line, "'" + e.key + "' does not belong in [model], which holds the "
							 "parameters of [sim] model; several models are [[model]] "
							 "tables with a name and a type");
			auto v = get_number(e, "model parameter '" + e.key + "'");
			if (!v)
				return v.error();
			m->params.push_back({ e.key, *v, e.line });
		}
		return Ok{};
	}

	Status parse_models(const toml::table &root)
	{
		std::optional<Entry> e = lookup(root, "model");
		int where = sc_.sim.line ? sc_.sim.line : 1;
		if (e && e->node->is_array() && (e->node->as_array()->empty() || e->node->is_array_of_tables()))
			return parse_model_array(*e->node->as_array(), e->line);
		if (e && !e->node->is_table())
			return err(e->line, "'model' must be a [model] table of parameters or [[model]] tables, not " +
						    std::string(type_name(*e->node)));
		if (!sim_model_)
			return err(e ? e->line : where,
				   e ? "[model] holds the parameters of [sim] model, which is missing"
				     : "no model: set [sim] model = \"pendulum\" (or another), or add [[model]] tables");
		// DESIGN's single-model form: named after its type, or the file's stem.
		ModelSpec m = *sim_model_;
		std::string stem = m.type.substr(m.type.rfind('/') + 1);
		m.name = is_model_path(m.type) ? stem.substr(0, stem.rfind('.')) : m.type;
		if (!is_identifier(m.name))
			return err(m.line, "cannot name a model '" + m.name + "' (signal names start with an "
									   "identifier); use a [[model]] table with a name");
		m.type = resolve_type(m.type);
		if (e)
			if (Status s = parse_params(*e->node->as_table(), &m, {}); !s)
				return s;
		sc_.models.push_back(std::move(m));
		return Ok{};
	}

	Status parse_model_array(const toml::array &a, int line)
	{
		if (sim_model_)
			return err(sim_model_->line, "[sim] model cannot be combined with [[model]] tables: give each "
						     "[[model]] its type");
		std::map<std::string, int> seen;
		for (const toml::node &n : a) {
			const toml::table &t = *n.as_table();
			ModelSpec m;
			m.line = line_of(t);
			auto es = entries(t);
			const Entry *name = find(es, "name");
			const Entry *type = find(es, "type");
			if (!name || !type)
				return err(m.line, std::string("[[model]] needs a ") + (name ? "type" : "name") +
							   " (and numeric parameters)");
			auto nm = get_string(*name, "\"left\"");
			if (!nm)
				return nm.error();
			if (!is_identifier(*nm))
				return err(name->line, "model name '" + *nm + "' is not an identifier (letters, digits, _)");
			if (seen.count(*nm))
				return err(name->line, "model name '" + *nm + "' is already used at line " +
							       std::to_string(seen[*nm]));
			seen[*nm] = name->line;
			auto ty = get_string(*type, "\"pendulum\"");
			if (!ty)
				return ty.error();
			if (ty->empty())
				return err(type->line, "model type is empty");
			m.name = *nm;
			m.type = resolve_type(*ty);
			if (Status s = parse_params(t, &m, { "name", "type" }); !s)
				return s;
			sc_.models.push_back(std::move(m));
		}
		if (sc_.models.empty())
			return err(line, "no model: add [[model]] tables");
		return Ok{};
	}

	Status parse_devices(const toml::table &root)
	{
		auto tables = table_array(root, "device");
		if (!tables)
			return tables.error();
		for (const toml::table *t : *tables)
			if (Status s = parse_device(*t); !s)
				return s;
		return Ok{};
	}

	Status parse_device(const toml::table &t)
	{
		using D = DeviceSpec;
		D d;
		d.line = line_of(t);
		if (Status s = check_keys(t, "in [[device]]",
					  { "path", "kind", "signals", "format", "mode", "rate", "limit" });
		    !s)
			return s;
		auto es = entries(t);
		const Entry *kind = find(es, "kind");
		const Entry *path = find(es, "path");
		const Entry *signals = find(es, "signals");
		for (auto [entry, key] : { std::pair{ kind, "kind" }, { path, "path" }, { signals, "signals" } })
			if (!entry)
				return err(d.line, std::string("[[device]] needs '") + key + "'");

		auto k = get_string(*kind, "\"sensor\"");
		if (!k)
			return k.error();
		if (*k != "sensor" && *k != "actuator")
			return err(kind->line, "kind must be \"sensor\" or \"actuator\", not \"" + *k + "\"");
		d.kind = *k == "sensor" ? D::Kind::Sensor : D::Kind::Actuator;
		bool sensor = d.kind == D::Kind::Sensor;

		auto p = get_string(*path, "\"/dev/tcs/pendulum/state\"");
		if (!p)
			return p.error();
		if (!is_normal_absolute(*p))
			return err(path->line, "device path '" + *p + "' must be absolute and normal (no '.', '..', "
										"'//' or trailing '/')");
		for (const D &other : sc_.devices)
			if (other.path == *p)
				return err(path->line, "device path '" + *p + "' is already used at line " +
								std::to_string(other.line));
		d.path = *p;

		if (Status s = parse_signals(*signals, &d); !s)
			return s;

		if (const Entry *f = find(es, "format")) {
			auto v = get_string(*f, "\"text\"");
			if (!v)
				return v.error();
			if (*v != "text" && *v != "binary")
				return err(f->line, "format must be \"text\" or \"binary\", not \"" + *v + "\"");
			d.format = *v == "text" ? D::Format::Text : D::Format::Binary;
		}

		const Entry *mode = find(es, "mode");
		const Entry *rate = find(es, "rate");
		const Entry *limit = find(es, "limit");
		if (sensor && limit)
			return err(limit->line, "'limit' applies to actuators only, not to a sensor");
		if (!sensor && (mode || rate))
			return err((mode ? mode : rate)->line,
				   "'" + (mode ? mode : rate)->key +
					   "' applies to sensors only: an actuator takes each command as it is written");
		if (mode) {
			auto v = get_string(*mode, "\"stream\"");
			if (!v)
				return v.error();
			if (*v != "stream" && *v != "latest")
				return err(mode->line, "mode must be \"stream\" or \"latest\", not \"" + *v + "\"");
			d.mode = *v == "stream" ? D::Mode::Stream : D::Mode::Latest;
		}
		if (sensor && d.mode == D::Mode::Latest && rate)
			return err(rate->line, "'rate' applies only to mode = \"stream\": a \"latest\" sensor "
					       "answers every read with the current value");
		if (sensor && d.mode == D::Mode::Stream) {
			if (!rate)
				return err(d.line, "a stream sensor needs a rate, such as rate = \"1kHz\"");
			auto text = get_string(*rate, "\"1kHz\"");
			if (!text)
				return text.error();
			auto hz = parse_rate_hz(*text);
			if (!hz)
				return err(rate->line, "rate: " + hz.error().message);
			d.rate_hz = *hz;
			d.period_ns = rate_period_ns(*hz);
		}
		if (limit) {
			auto v = get_number(*limit, "limit");
			if (!v)
				return v.error();
			if (*v <= 0)
				return err(limit->line, "limit must be positive (it bounds the command's magnitude)");
			d.limit = *v;
		}
		sc_.devices.push_back(std::move(d));
		return Ok{};
	}

	Status parse_signals(const Entry &e, DeviceSpec *d)
	{
		const toml::array *a = e.node->as_array();
		if (!a)
			return err(e.line, "signals must be an array of strings such as [\"pendulum.hinge.position\"], "
					   "not " + std::string(type_name(*e.node)));
		if (a->empty())
			return err(e.line, "signals is empty: a device carries at least one signal");
		bool actuator = d->kind == DeviceSpec::Kind::Actuator;
		for (const toml::node &n : *a) {
			int line = line_of(n);
			if (!n.is_string())
				return err(line, "signals must be strings, not " + std::string(type_name(n)));
			const std::string name = unshift(n.as_string()->get());
			auto parts = split_signal_name(name);
			if (!parts)
				return err(line, "signal '" + name + "' is not <model>.<part>.<field> with field one of "
								     "position, velocity, effort, pose, twist");
			if (!has_model(parts->model))
				return err(line, "signal '" + name + "': the scenario has no model '" +
							 std::string(parts->model) + "' (models: " + model_names() + ")");
			if (actuator && parts->field != "effort")
				return err(line, "actuator signal '" + name + "' is not an effort: actuators drive "
										"<model>.<joint>.effort");
			for (const SignalRef &s : d->signals)
				if (s.name == name)
					return err(line, "signal '" + name + "' is listed twice");
			if (actuator)
				for (const DeviceSpec &o : sc_.devices)
					if (o.kind == DeviceSpec::Kind::Actuator)
						for (const SignalRef &s : o.signals)
							if (s.name == name)
								return err(line, "signal '" + name + "' is already driven by " +
											 o.path + " (line " +
											 std::to_string(s.line) + ")");
			d->signals.push_back({ name, line });
		}
		return Ok{};
	}

	bool has_model(std::string_view name) const
	{
		for (const ModelSpec &m : sc_.models)
			if (m.name == name)
				return true;
		return false;
	}

	std::string model_names() const
	{
		std::vector<std::string> v;
		for (const ModelSpec &m : sc_.models)
			v.push_back(m.name);
		return join(v);
	}

	Status parse_controllers(const toml::table &root)
	{
		auto tables = table_array(root, "controller");
		if (!tables)
			return tables.error();
		for (const toml::table *t : *tables) {
			ControllerEntry c;
			c.line = line_of(*t);
			if (Status s = check_keys(*t, "in [[controller]]", { "command", "cpu_scale" }); !s)
				return s;
			auto es = entries(*t);
			const Entry *command = find(es, "command");
			if (!command)
				return err(c.line, "[[controller]] needs a command");
			auto text = get_string(*command, "\"examples/pendulum_pd --rate 1000\"");
			if (!text)
				return text.error();
			auto argv = split_command(*text);
			if (!argv)
				return err(command->line, "command: " + argv.error().message);
			if (argv->empty())
				return err(command->line, "command is empty");
			c.command = *text;
			c.argv = std::move(*argv);
			if (const Entry *scale = find(es, "cpu_scale")) {
				auto v = get_number(*scale, "cpu_scale");
				if (!v)
					return v.error();
				if (*v <= 0 || *v > 1e6)
					return err(scale->line, "cpu_scale must be positive (virtual seconds per CPU "
								"second, at most 1e6)");
				c.cpu_scale = *v;
			}
			sc_.controllers.push_back(std::move(c));
		}
		return Ok{};
	}

	Scenario sc_;
	std::string dir_;                    // the file's folder, for relative model paths
	std::optional<ModelSpec> sim_model_; // [sim] model, before the models are known
};

} // namespace

Error scenario_error(const Scenario &scenario, int line, const std::string &what)
{
	return Error{ scenario.file + ":" + std::to_string(line) + ": " + what };
}

Status check_signals(const Scenario &scenario, const std::vector<std::string> &known)
{
	std::unordered_set<std::string_view> set(known.begin(), known.end());
	for (const DeviceSpec &d : scenario.devices)
		for (const SignalRef &s : d.signals) {
			if (set.count(s.name))
				continue;
			std::string model = s.name.substr(0, s.name.find('.'));
			std::vector<std::string> theirs;
			for (const std::string &k : known)
				if (k.size() > model.size() && k.compare(0, model.size(), model) == 0 && k[model.size()] == '.')
					theirs.push_back(k);
			return scenario_error(scenario, s.line,
					      "unknown signal '" + s.name + "' (model '" + model +
						      (theirs.empty() ? "' has no signals)" : "' has: " + join(theirs) + ")"));
		}
	return Ok{};
}

Result<Scenario> parse_scenario_text(const std::string &text, const std::string &name_for_errors)
{
	return Parser(name_for_errors, "").run(text);
}

Result<Scenario> parse_scenario_file(const std::string &path)
{
	auto text = read_file(path, kMaxScenarioBytes);
	if (!text)
		return text.error();
	size_t slash = path.rfind('/');
	std::string dir = slash == std::string::npos ? "" : path.substr(0, slash == 0 ? 1 : slash);
	return Parser(path, dir).run(*text);
}

} // namespace tcs
