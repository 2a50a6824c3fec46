// The simulated world as the coordinator sees it: a simhost plug-in's
// world behind the C ABI, with signals looked up by name and the wall-clock
// cost of every step measured (the TCS paper's Figure 1 quantity).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "error.h"
#include "sensor_models.h"
#include "tcs/simhost.h"

namespace tcs {

// A scenario's [[sensor]]: the model on one signal, by name.
struct SensorConfig {
	std::string signal;
	double noise = 0, bias = 0, resolution = 0;
	int64_t latency_ns = 0;
	double rate_hz = 0; // 0: the signal's own rate (tcs_sim_signal_info), else every step
};

struct ModelInstance {
	std::string name;
	std::string type;
	std::vector<std::pair<std::string, double>> params;
};

class SimWorld {
public:
	// A world of these models from the plug-in (the built-in ODE one when
	// plugin is null), stepping step_ns at a time.
	static Result<std::unique_ptr<SimWorld>> create(const std::vector<ModelInstance> &models, int64_t step_ns,
							const tcs_simhost_plugin *plugin = nullptr);
	~SimWorld();
	SimWorld(const SimWorld &) = delete;
	SimWorld &operator=(const SimWorld &) = delete;

	Status step();
	int64_t step_ns() const { return step_ns_; }
	// The step its models' files ask for (an SDF world's), or 0.
	int64_t file_step_ns() const;
	int64_t steps() const { return steps_; }
	// Wall-clock cost of the last step, and extremes so far (ns).
	int64_t last_step_wall_ns() const { return last_wall_; }

	size_t signal_count() const;
	const tcs_sim_signal_info &signal(size_t index) const;
	// The index of a signal by name, or -1.
	long find(const std::string &name) const;
	// What sensors see from now on: these models, and every signal the
	// plug-in samples at a rate of its own held between its samples (key:
	// the run's seed, mixed; never 0). An unknown signal is an error.
	Status sense(const std::vector<SensorConfig> &configs, uint64_t key);
	// Appends signal index's current values to out: the truth.
	void read(size_t index, std::vector<double> &out) const;
	// The same as a sensor sees it (a device's read): sense()'s model of
	// it, if it has one.
	void read_sensed(size_t index, std::vector<double> &out) const;
	// Sets a writable signal (held from the next step on).
	void write(size_t index, const double *values);
	// Every signal's values, in order: the world as read from something
	// that steps it elsewhere (an agent's view of its host's world). From
	// then on read() returns these.
	void mirror(std::vector<double> all);
	// How many values all the signals have together.
	size_t value_count() const;
	// Every signal's values now, in order (what mirror() takes).
	void read_all(std::vector<double> &out) const;

private:
	SimWorld() = default;
	const tcs_simhost_plugin *plugin_ = nullptr;
	tcs_sim *sim_ = nullptr;
	int64_t step_ns_ = 0;
	int64_t steps_ = 0;
	int64_t last_wall_ = 0;
	const std::vector<size_t> &offsets() const;
	std::unique_ptr<SensorModels> sensors_; // null: sensors see the truth
	std::vector<double> mirror_;          // empty: not a mirror
	mutable std::vector<size_t> offsets_; // see offsets()
};

} // namespace tcs
