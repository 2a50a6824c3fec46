// SensorModels: history, sampling and noise (see sensor_models.h).
#include "sensor_models.h"

#include <cmath>
#include <numbers>

#include "tcs/random_stream.h"

namespace tcs {

namespace {

uint64_t name_hash(const std::string &s)
{
	uint64_t h = 0xcbf29ce484222325ull; // FNV-1a
	for (unsigned char c : s)
		h = (h ^ c) * 0x100000001b3ull;
	return h;
}

// A uniform draw in (0, 1]: 53 bits of a block.
double uniform(uint64_t block)
{
	return (double)((block >> 11) + 1) * 0x1.0p-53;
}

} // namespace

SensorModels::SensorModels(std::vector<SensorModel> models, uint64_t key)
{
	for (SensorModel &m : models) {
		State s;
		s.key = tcs_random_key(key, name_hash(m.signal));
		s.sample.assign(m.width, 0.0);
		if (slot_.size() <= m.index)
			slot_.resize(m.index + 1, -1);
		slot_[m.index] = (int)models_.size();
		s.m = std::move(m);
		models_.push_back(std::move(s));
	}
}

// Box-Muller: two draws of the stream a normal deviate.
double gaussian_draw(uint64_t key, uint64_t &drawn)
{
	double u1 = uniform(tcs_random_block(key, drawn++));
	double u2 = uniform(tcs_random_block(key, drawn++));
	return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

double SensorModels::gaussian(State &s)
{
	return gaussian_draw(s.key, s.drawn);
}

void SensorModels::observe(int64_t t_ns, const std::function<void(size_t, double *)> &truth)
{
	for (State &s : models_) {
		// (Each step: the buffer of an entry let go is taken again.)
		std::vector<double> now = std::move(s.spare);
		now.resize(s.m.width);
		truth(s.m.index, now.data());
		s.history.emplace_back(t_ns, std::move(now));
		// Kept: the latest at or before t - latency, and what follows.
		const int64_t seen_at = t_ns - s.m.latency_ns;
		while (s.history.size() > 1 && s.history[1].first <= seen_at) {
			s.spare = std::move(s.history.front().second);
			s.history.pop_front();
		}
		if (t_ns < s.next_sample)
			continue;
		// The first sample is at the start; then one each period on the
		// grid (a period shorter than the step: each step).
		s.next_sample = s.m.period_ns > 0 ? (t_ns / s.m.period_ns + 1) * s.m.period_ns : t_ns + 1;
		const std::vector<double> &seen = s.history.front().second;
		for (uint32_t k = 0; k < s.m.width; k++) {
			double v = seen[k] + s.m.bias;
			if (s.m.noise > 0)
				v += s.m.noise * gaussian(s);
			if (s.m.resolution > 0)
				v = std::round(v / s.m.resolution) * s.m.resolution;
			s.sample[k] = v;
		}
	}
}

bool SensorModels::read(size_t index, std::vector<double> &out) const
{
	if (index >= slot_.size() || slot_[index] < 0)
		return false;
	const State &s = models_[(size_t)slot_[index]];
	out.insert(out.end(), s.sample.begin(), s.sample.end());
	return true;
}

} // namespace tcs
