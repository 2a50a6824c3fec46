// The simulated world as the coordinator sees it: a simhost plug-in's
// world behind the C ABI, with signals looked up by name and the wall-clock
// cost of every step measured (the TCS paper's Figure 1 quantity).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "error.h"
#include "tcs/simhost.h"

namespace tcs {

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
	int64_t steps() const { return steps_; }
	// Wall-clock cost of the last step, and extremes so far (ns).
	int64_t last_step_wall_ns() const { return last_wall_; }

	size_t signal_count() const;
	const tcs_sim_signal_info &signal(size_t index) const;
	// The index of a signal by name, or -1.
	long find(const std::string &name) const;
	// Appends signal index's current values to out.
	void read(size_t index, std::vector<double> &out) const;
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
	std::vector<double> mirror_;          // empty: not a mirror
	mutable std::vector<size_t> offsets_; // see offsets()
};

} // namespace tcs
