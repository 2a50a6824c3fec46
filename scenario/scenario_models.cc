// Reading [sim] and the models of a scenario (see scenario_models.h).
#include "scenario_models.h"

#include <algorithm>
#include <map>

#include "scenario_units.h"

namespace tcs::scenario_parse {

namespace {

constexpr int64_t kMinStepNs = 10000;      // 10 us
constexpr int64_t kMaxStepNs = 1000000000; // 1 s

bool ends_with(std::string_view s, std::string_view tail)
{
	return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

bool is_model_path(std::string_view type)
{
	return type.find('/') != std::string_view::npos || ends_with(type, ".sdf") || ends_with(type, ".urdf");
}

std::string resolve_type(const ScenarioReader &r, const std::string &type)
{
	if (!is_model_path(type) || type[0] == '/' || r.dir.empty())
		return type;
	return r.dir + (r.dir.back() == '/' ? "" : "/") + type;
}

// A model's numeric parameters: every key of t but those in `skip`.
Status parse_params(ScenarioReader &r, const toml::table &t, ModelSpec *m, std::initializer_list<const char *> skip)
{
	for (const Entry &e : entries(t)) {
		if (std::find(skip.begin(), skip.end(), e.key) != skip.end())
			continue;
		if ((e.key == "name" || e.key == "type") && !e.node->is_number())
			return r.err(e.line, "'" + e.key + "' does not belong in [model], which holds the "
						 "parameters of [sim] model; several models are [[model]] "
						 "tables with a name and a type");
		auto v = r.get_number(e, "model parameter '" + e.key + "'");
		if (!v)
			return v.error();
		m->params.push_back({ e.key, *v, e.line });
	}
	return Ok{};
}

Status parse_model_array(ScenarioReader &r, const toml::array &a, int line)
{
	if (r.sim_model)
		return r.err(r.sim_model->line, "[sim] model cannot be combined with [[model]] tables: give each "
					     "[[model]] its type");
	std::map<std::string, int> seen;
	for (const toml::node &n : a) {
		const toml::table &t = *n.as_table();
		ModelSpec m;
		m.line = line_of(t);
		auto es = entries(t);
		const Entry *name = find_entry(es, "name");
		const Entry *type = find_entry(es, "type");
		if (!name || !type)
			return r.err(m.line, std::string("[[model]] needs a ") + (name ? "type" : "name") +
						   " (and numeric parameters)");
		auto nm = r.get_string(*name, "\"left\"");
		if (!nm)
			return nm.error();
		if (!is_identifier(*nm))
			return r.err(name->line, "model name '" + *nm + "' is not an identifier (letters, digits, _)");
		if (seen.count(*nm))
			return r.err(name->line, "model name '" + *nm + "' is already used at line " +
						       std::to_string(seen[*nm]));
		seen[*nm] = name->line;
		auto ty = r.get_string(*type, "\"pendulum\"");
		if (!ty)
			return ty.error();
		if (ty->empty())
			return r.err(type->line, "model type is empty");
		m.name = *nm;
		m.type = resolve_type(r, *ty);
		if (Status s = parse_params(r, t, &m, { "name", "type" }); !s)
			return s;
		r.sc.models.push_back(std::move(m));
	}
	if (r.sc.models.empty())
		return r.err(line, "no model: add [[model]] tables");
	return Ok{};
}

} // namespace

Status parse_sim(const toml::table &root, ScenarioReader &r)
{
	std::optional<Entry> e = lookup(root, "sim");
	if (!e)
		return Ok{};
	const toml::table *t = e->node->as_table();
	if (!t)
		return r.err(e->line, "'sim' must be a table ([sim]), not " + std::string(type_name(*e->node)));
	r.sc.sim.line = line_of(*t);
	if (Status s = r.check_keys(*t, "in [sim]", { "step", "model" }); !s)
		return s;
	auto es = entries(*t);
	if (const Entry *step = find_entry(es, "step")) {
		r.sc.sim.line = step->line;
		auto text = r.get_string(*step, "\"1ms\"");
		if (!text)
			return text.error();
		auto ns = parse_duration_ns(*text);
		if (!ns)
			return r.err(step->line, "step: " + ns.error().message);
		if (*ns < kMinStepNs || *ns > kMaxStepNs)
			return r.err(step->line, "step '" + *text + "' is out of range (10us to 1s)");
		r.sc.sim.step_ns = *ns;
	}
	if (const Entry *model = find_entry(es, "model")) {
		auto type = r.get_string(*model, "\"pendulum\"");
		if (!type)
			return type.error();
		if (type->empty())
			return r.err(model->line, "model is empty (built-in: pendulum, cartpole, double_pendulum, "
						"boxes; or a .sdf/.urdf path)");
		r.sim_model = ModelSpec{ "", *type, {}, model->line };
	}
	return Ok{};
}

Status parse_models(const toml::table &root, ScenarioReader &r)
{
	std::optional<Entry> e = lookup(root, "model");
	int where = r.sc.sim.line ? r.sc.sim.line : 1;
	if (e && e->node->is_array() && (e->node->as_array()->empty() || e->node->is_array_of_tables()))
		return parse_model_array(r, *e->node->as_array(), e->line);
	if (e && !e->node->is_table())
		return r.err(e->line, "'model' must be a [model] table of parameters or [[model]] tables, not " +
					    std::string(type_name(*e->node)));
	if (!r.sim_model)
		return r.err(e ? e->line : where,
			   e ? "[model] holds the parameters of [sim] model, which is missing"
			     : "no model: set [sim] model = \"pendulum\" (or another), or add [[model]] tables");
	// DESIGN's single-model form: named after its type, or the file's stem.
	ModelSpec m = *r.sim_model;
	std::string stem = m.type.substr(m.type.rfind('/') + 1);
	m.name = is_model_path(m.type) ? stem.substr(0, stem.rfind('.')) : m.type;
	if (!is_identifier(m.name))
		return r.err(m.line, "cannot name a model '" + m.name + "' (signal names start with an "
								   "identifier); use a [[model]] table with a name");
	m.type = resolve_type(r, m.type);
	if (e)
		if (Status s = parse_params(r, *e->node->as_table(), &m, {}); !s)
			return s;
	r.sc.models.push_back(std::move(m));
	return Ok{};
}

} // namespace tcs::scenario_parse
