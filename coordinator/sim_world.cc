// SimWorld: the plug-in calls, and their errors made into Errors.
#include "sim_world.h"

#include <time.h>

#include <algorithm>
#include <cmath>

#include "tcs/vtime.h"

namespace tcs {

Result<std::unique_ptr<SimWorld>> SimWorld::create(const std::vector<ModelInstance> &models, int64_t step_ns,
						   const tcs_simhost_plugin *plugin)
{
	std::unique_ptr<SimWorld> w(new SimWorld());
	w->plugin_ = plugin ? plugin : tcs_simhost_ode_plugin();
	w->step_ns_ = step_ns;
	if (w->plugin_->abi_version != TCS_SIMHOST_ABI_VERSION)
		return Error{ std::string("simulation plug-in '") + w->plugin_->name + "' speaks another ABI version" };
	// The C ABI wants arrays of C strings and numbers.
	std::vector<std::vector<const char *>> keys(models.size());
	std::vector<std::vector<double>> values(models.size());
	std::vector<tcs_sim_model> cm(models.size());
	for (size_t i = 0; i < models.size(); i++) {
		for (const auto &[k, v] : models[i].params) {
			keys[i].push_back(k.c_str());
			values[i].push_back(v);
		}
		cm[i].name = models[i].name.c_str();
		cm[i].type = models[i].type.c_str();
		cm[i].param_keys = keys[i].data();
		cm[i].param_values = values[i].data();
		cm[i].nparams = keys[i].size();
	}
	char err[512] = "";
	w->sim_ = w->plugin_->create(cm.data(), cm.size(), step_ns, err, sizeof err);
	if (!w->sim_)
		return Error{ err[0] ? err : "the simulation could not be created" };
	return w;
}

SimWorld::~SimWorld()
{
	if (sim_)
		plugin_->destroy(sim_);
}

Status SimWorld::step()
{
	struct timespec a, b;
	char err[512] = "";
	clock_gettime(CLOCK_MONOTONIC, &a);
	int r = plugin_->step(sim_, err, sizeof err);
	clock_gettime(CLOCK_MONOTONIC, &b);
	last_wall_ = tcs_ts_to_ns(&b) - tcs_ts_to_ns(&a);
	steps_++;
	if (r != 0)
		return Error{ std::string("the simulation failed to step: ") + (err[0] ? err : "no reason given") };
	if (sensors_)
		sensors_->observe(steps_ * step_ns_, [this](size_t i, double *out) { plugin_->read(sim_, i, out); });
	return Ok{};
}

Status SimWorld::sense(const std::vector<SensorConfig> &configs, uint64_t key)
{
	std::vector<SensorModel> models;
	for (const SensorConfig &c : configs) {
		long i = find(c.signal);
		if (i < 0)
			return Error{ "no signal '" + c.signal + "' for a sensor model" };
		const tcs_sim_signal_info &info = signal((size_t)i);
		const double hz = c.rate_hz > 0 ? c.rate_hz : info.rate_hz;
		models.push_back({ c.signal, (size_t)i, info.width, c.noise, c.bias, c.resolution, c.latency_ns,
				   hz > 0 ? (int64_t)std::llround(1e9 / hz) : 0 });
	}
	for (size_t i = 0, n = signal_count(); i < n; i++) {
		const tcs_sim_signal_info &info = signal(i);
		if (info.rate_hz > 0 && std::none_of(models.begin(), models.end(), [i](const SensorModel &m) { return m.index == i; }))
			models.push_back({ info.name, i, info.width, 0, 0, 0, 0, (int64_t)std::llround(1e9 / info.rate_hz) });
	}
	if (models.empty()) {
		sensors_.reset();
		return Ok{};
	}
	sensors_ = std::make_unique<SensorModels>(std::move(models), key);
	sensors_->observe(steps_ * step_ns_, [this](size_t i, double *out) { plugin_->read(sim_, i, out); });
	return Ok{};
}

void SimWorld::read_sensed(size_t index, std::vector<double> &out) const
{
	if (!sensors_ || !mirror_.empty() || !sensors_->read(index, out))
		read(index, out);
}

int64_t SimWorld::file_step_ns() const
{
	return plugin_->file_step_ns ? plugin_->file_step_ns(sim_) : 0;
}

size_t SimWorld::signal_count() const
{
	return plugin_->signal_count(sim_);
}

const tcs_sim_signal_info &SimWorld::signal(size_t index) const
{
	return *plugin_->signal_info(sim_, index);
}

long SimWorld::find(const std::string &name) const
{
	for (size_t i = 0, n = signal_count(); i < n; i++)
		if (name == signal(i).name)
			return (long)i;
	return -1;
}

void SimWorld::read(size_t index, std::vector<double> &out) const
{
	size_t at = out.size();
	size_t width = signal(index).width;
	out.resize(at + width);
	if (!mirror_.empty()) {
		std::copy_n(mirror_.begin() + (long)offsets()[index], width, out.begin() + (long)at);
		return;
	}
	plugin_->read(sim_, index, out.data() + at);
}

void SimWorld::read_all(std::vector<double> &out) const
{
	out.clear();
	for (size_t i = 0, n = signal_count(); i < n; i++)
		read(i, out);
}

// Where each signal's values begin in read_all()'s order, and the total
// last: the signal table never changes, so made once.
const std::vector<size_t> &SimWorld::offsets() const
{
	if (offsets_.empty()) {
		size_t at = 0;
		for (size_t i = 0, n = signal_count(); i < n; i++) {
			offsets_.push_back(at);
			at += signal(i).width;
		}
		offsets_.push_back(at);
	}
	return offsets_;
}

void SimWorld::mirror(std::vector<double> all)
{
	// A grant of another size is another world's: the caller checked.
	if (all.size() == value_count())
		mirror_ = std::move(all);
}

size_t SimWorld::value_count() const
{
	return offsets().back();
}

void SimWorld::write(size_t index, const double *values)
{
	plugin_->write(sim_, index, values);
}

} // namespace tcs
