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

bool is_robot_file(std::string_view path)
{
	return ends_with(path, ".urdf") || ends_with(path, ".sdf") || ends_with(path, ".world");
}

bool is_model_path(std::string_view type)
{
	return type.find('/') != std::string_view::npos || is_robot_file(type);
}

std::string resolve_type(const ScenarioReader &r, const std::string &type)
{
	if (!is_model_path(type) || type[0] == '/' || r.dir.empty())
		return type;
	return r.dir + (r.dir.back() == '/' ? "" : "/") + type;
}

// A robot file's placement (DESIGN §8) as numeric parameters, which is
// all the plug-in ABI carries: fixed = 0/1, pose = six numbers as pose.x
// ... pose.yaw, a joint's initial position as initial_position.<joint>.
constexpr const char *kPoseKeys[] = { "pose.x", "pose.y", "pose.z", "pose.roll", "pose.pitch", "pose.yaw" };

Status parse_placement(ScenarioReader &r, const Entry &e, ModelSpec *m)
{
	if (e.key == "fixed") {
		const auto *b = e.node->as_boolean();
		if (!b)
			return r.err(e.line, "fixed must be true or false, not " + std::string(type_name(*e.node)));
		m->params.push_back({ "fixed", b->get() ? 1.0 : 0.0, e.line });
		return Ok{};
	}
	if (e.key == "pose") {
		const auto *a = e.node->as_array();
		if (!a || a->size() != 6)
			return r.err(e.line, "pose must be six numbers: [x, y, z, roll, pitch, yaw] (m, rad)");
		for (size_t i = 0; i < 6; i++) {
			auto v = r.get_number(Entry{ e.line, "pose", a->get(i) }, "pose");
			if (!v)
				return v.error();
			m->params.push_back({ kPoseKeys[i], *v, e.line });
		}
		return Ok{};
	}
	// initial_positions, initial_velocities: { joint = number, ... }
	const auto *t = e.node->as_table();
	if (!t)
		return r.err(e.line, e.key + " must be a table of joint names and numbers, as " + e.key +
					     " = { joint1 = 0.3 }");
	const std::string prefix = e.key == "initial_positions" ? "initial_position." : "initial_velocity.";
	for (const Entry &j : entries(*t)) {
		auto v = r.get_number(j, e.key + " of joint '" + j.key + "'");
		if (!v)
			return v.error();
		m->params.push_back({ prefix + j.key, *v, j.line });
	}
	return Ok{};
}

bool is_placement(const std::string &key)
{
	return key == "fixed" || key == "pose" || key == "initial_positions" || key == "initial_velocities";
}

// A model's parameters: every key of t but those in `skip`, numbers or a
// robot file's placement.
Status parse_params(ScenarioReader &r, const toml::table &t, ModelSpec *m, std::initializer_list<const char *> skip)
{
	for (const Entry &e : entries(t)) {
		if (std::find(skip.begin(), skip.end(), e.key) != skip.end())
			continue;
		if ((e.key == "name" || e.key == "type" || e.key == "file") && !e.node->is_number())
			return r.err(e.line, "'" + e.key + "' does not belong in [model], which holds the "
						 "parameters of [sim] model; several models are [[model]] "
						 "tables with a name and a type or file");
		if (is_placement(e.key)) {
			if (Status s = parse_placement(r, e, m); !s)
				return s;
			continue;
		}
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
		const Entry *file = find_entry(es, "file");
		if (type && file)
			return r.err(file->line, "[[model]] has a type (line " + std::to_string(type->line) +
							 ") and a file: give one (a built-in type, or a .urdf/.sdf file)");
		if (!type)
			type = file;
		if (!name || !type)
			return r.err(m.line, std::string("[[model]] needs a ") +
						   (name ? "type (pendulum, cartpole, double_pendulum, boxes) or a file "
							   "(.urdf, .sdf)"
							 : "name") +
						   " (and parameters)");
		auto nm = r.get_string(*name, "\"left\"");
		if (!nm)
			return nm.error();
		if (!is_identifier(*nm))
			return r.err(name->line, "model name '" + *nm + "' is not an identifier (letters, digits, _)");
		if (seen.count(*nm))
			return r.err(name->line, "model name '" + *nm + "' is already used at line " +
						       std::to_string(seen[*nm]));
		seen[*nm] = name->line;
		auto ty = r.get_string(*type, type == file ? "\"robots/arm.urdf\"" : "\"pendulum\"");
		if (!ty)
			return ty.error();
		if (ty->empty())
			return r.err(type->line, "model " + type->key + " is empty");
		if (type == file && !is_robot_file(*ty))
			return r.err(file->line, "file '" + *ty + "' is not a robot description: a .urdf, .sdf or "
								  ".world file");
		m.name = *nm;
		m.type = resolve_type(r, *ty);
		if (Status s = parse_params(r, t, &m, { "name", "type", "file" }); !s)
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
		r.sc.sim.step_given = true;
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
