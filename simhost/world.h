// A tcs world (the ABI's tcs_sim): the model instances a scenario names,
// one flat table of their signals, and the fixed step that advances them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "model.h"
#include "error.h"
#include "tcs/simhost.h"

namespace tcs::sim {

// The model types the ODE plug-in knows, and their names NULL-terminated
// for the plug-in table.
extern const ModelType *const kModelTypes[];
extern const char *const kModelTypeNames[];

class World {
public:
	static Result<std::unique_ptr<World>> create(const struct tcs_sim_model *models, size_t nmodels,
						     int64_t step_ns);

	Status step();
	size_t signal_count() const { return infos_.size(); }
	const struct tcs_sim_signal_info *signal_info(size_t index) const
	{
		return index < infos_.size() ? &infos_[index] : nullptr;
	}
	// -1 for a bad index; write also for a signal that is not writable or
	// a value that is not finite (it would poison the state for good).
	int read(size_t index, double *out) const;
	// An SDF world file's step (ns), the first such; 0 if none.
	int64_t file_step_ns() const { return file_step_ns_; }
	int write(size_t index, const double *values);

private:
	struct Slot {
		Model *model;
		uint32_t local;
	};

	Status add(const struct tcs_sim_model &spec);
	Status add_robot_file(const struct tcs_sim_model &spec);
	// A model's name: one part of signal names, and no other model's.
	Status check_name(const struct tcs_sim_model &spec, const std::string &who) const;
	// A model's signals appended to the table.
	void take(std::unique_ptr<Model> model, const std::string &name);

	double dt_ = 0;
	int64_t file_step_ns_ = 0;
	int64_t steps_ = 0;
	std::vector<std::unique_ptr<Model>> models_;
	std::vector<std::string> model_names_;
	std::vector<SignalDesc> descs_;
	std::vector<Slot> slots_;
	std::vector<struct tcs_sim_signal_info> infos_; // points into descs_
};

} // namespace tcs::sim
