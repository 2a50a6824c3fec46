// What sensors see of the world (DESIGN §8): a signal's value `latency`
// ago, plus a bias and Gaussian noise, quantised, sampled at the sensor's
// rate and held between samples. The noise is drawn from --seed's stream
// (tcs/random_stream.h), one stream per signal, by sample, never by read:
// what a controller reads does not depend on when or how often it reads,
// and a seeded run repeats whatever the machine.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

namespace tcs {

struct SensorModel {
	std::string signal; // its name (its noise stream's)
	size_t index = 0;   // the world's signal index
	uint32_t width = 1;
	double noise = 0, bias = 0, resolution = 0; // resolution 0: none
	int64_t latency_ns = 0;
	int64_t period_ns = 0; // 0: a sample each step
};

// A standard normal deviate from stream key, its drawn-th and next
// blocks (drawn moves on by two): the same draws for the same key.
double gaussian_draw(uint64_t key, uint64_t &drawn);

class SensorModels {
public:
	// key: the run's seed mixed (tcs_random_key), never 0.
	SensorModels(std::vector<SensorModel> models, uint64_t key);
	bool empty() const { return models_.empty(); }
	// The world at t (after a step, or at the start): truth(index, out)
	// writes a signal's true values. Samples those due.
	void observe(int64_t t_ns, const std::function<void(size_t index, double *out)> &truth);
	// A modelled signal's last sample, appended to out; false if index has
	// no model.
	bool read(size_t index, std::vector<double> &out) const;

private:
	struct State {
		SensorModel m;
		uint64_t key = 0, drawn = 0;
		int64_t next_sample = 0;
		std::deque<std::pair<int64_t, std::vector<double>>> history; // (t, truth), oldest first
		std::vector<double> sample;
		std::vector<double> spare; // a history entry's values, for the next
	};
	double gaussian(State &s);
	std::vector<State> models_;
	std::vector<int> slot_; // by signal index: its model's place in models_, or -1
};

} // namespace tcs
