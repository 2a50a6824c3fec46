// Creating a world from the scenario's model list (checking names, types
// and parameters), its signal table, and the step.
#include "world.h"

#include <cmath>
#include <cstdio>
#include <string_view>

#include "ode_init.h"
#include "robot_file.h"

namespace tcs::sim {

const ModelType *const kModelTypes[] = { &pendulum_model, &cartpole_model, &double_pendulum_model, &boxes_model,
					 nullptr };
const char *const kModelTypeNames[] = { "pendulum", "cartpole", "double_pendulum", "boxes", nullptr };

namespace {

const ModelType *find_type(const char *type)
{
	for (const ModelType *const *t = kModelTypes; *t; t++)
		if (std::string_view((*t)->type) == type)
			return *t;
	return nullptr;
}

std::string type_list()
{
	std::string s;
	for (const char *const *t = kModelTypeNames; *t; t++) {
		if (!s.empty())
			s += ", ";
		s += *t;
	}
	return s;
}

// A name becomes the first part of dotted signal names.
bool valid_name(std::string_view name)
{
	if (name.empty())
		return false;
	for (char c : name)
		if (c == '.' || c <= ' ' || c == 0x7f)
			return false;
	return true;
}

} // namespace

Result<std::unique_ptr<World>> World::create(const struct tcs_sim_model *models, size_t nmodels, int64_t step_ns)
{
	if (step_ns <= 0)
		return Error{ "the step must be positive (got " + std::to_string(step_ns) + " ns)" };
	if (nmodels > 0 && !models)
		return Error{ "no model list" };
	if (auto s = ode_ready(); !s)
		return s.error();

	std::unique_ptr<World> w(new World());
	w->dt_ = (double)step_ns * 1e-9;
	for (size_t i = 0; i < nmodels; i++)
		if (auto s = w->add(models[i]); !s)
			return s.error();

	// descs_ is complete: only now is it safe to point into its strings.
	w->infos_.reserve(w->descs_.size());
	for (const SignalDesc &d : w->descs_)
		w->infos_.push_back({ d.name.c_str(), d.width, d.flags, d.unit, d.rate_hz });
	return w;
}

Status World::add(const struct tcs_sim_model &spec)
{
	if (!spec.type)
		return Error{ "a model has no type (known: " + type_list() + ")" };
	if (is_robot_file(spec.type))
		return add_robot_file(spec);
	const ModelType *type = find_type(spec.type);
	if (!type)
		return Error{ std::string("unknown model type '") + spec.type + "' (known: " + type_list() + ")" };
	std::string who = std::string(spec.type) + " '" + (spec.name ? spec.name : "") + "'";
	if (auto s = check_name(spec, who); !s)
		return s;

	auto params = Params::parse(who, type->params, spec);
	if (!params)
		return params.error();
	auto model = type->make(spec.name, *params);
	if (!model)
		return Error{ who + ": " + model.error().message };

	take(std::move(*model), spec.name);
	return Ok{};
}

Status World::check_name(const struct tcs_sim_model &spec, const std::string &who) const
{
	if (!spec.name || !valid_name(spec.name))
		return Error{ who + ": a model's name must be non-empty, without dots or spaces" };
	for (const std::string &n : model_names_)
		if (n == spec.name)
			return Error{ who + ": another model has the same name" };
	return Ok{};
}

Status World::add_robot_file(const struct tcs_sim_model &spec)
{
	std::string who = std::string(spec.type) + " '" + (spec.name ? spec.name : "") + "'";
	if (auto s = check_name(spec, who); !s)
		return s;
	auto made = make_robot_file_models(spec);
	if (!made)
		return made.error();
	for (auto &m : made->models)
		take(std::move(m), spec.name);
	if (file_step_ns_ == 0)
		file_step_ns_ = made->step_ns;
	return Ok{};
}

void World::take(std::unique_ptr<Model> model, const std::string &name)
{
	size_t first = descs_.size();
	model->describe(descs_);
	for (size_t i = first; i < descs_.size(); i++)
		slots_.push_back({ model.get(), (uint32_t)(i - first) });
	models_.push_back(std::move(model));
	model_names_.push_back(name);
}

Status World::step()
{
	if (auto s = ode_ready(); !s)
		return s.error();
	for (size_t i = 0; i < models_.size(); i++) {
		if (auto s = models_[i]->step(dt_); !s) {
			char at[64];
			snprintf(at, sizeof at, " (step %lld)", (long long)steps_ + 1);
			return Error{ "model '" + model_names_[i] + "': " + s.error().message + at };
		}
	}
	steps_++;
	return Ok{};
}

int World::read(size_t index, double *out) const
{
	if (index >= slots_.size() || !out)
		return -1;
	slots_[index].model->read(slots_[index].local, out);
	return 0;
}

int World::write(size_t index, const double *values)
{
	if (index >= slots_.size() || !values || !(descs_[index].flags & TCS_SIM_SIGNAL_WRITABLE))
		return -1;
	for (uint32_t i = 0; i < descs_[index].width; i++)
		if (!std::isfinite(values[i]))
			return -1;
	slots_[index].model->write(slots_[index].local, values);
	return 0;
}

} // namespace tcs::sim
