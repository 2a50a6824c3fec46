// Model parameters: each model declares the keys it knows with their
// defaults and what makes a value valid; parse() checks what a scenario
// gave against that table and answers with a message naming the key.
#pragma once

#include <cmath>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "error.h"
#include "tcs/simhost.h"

namespace tcs::sim {

enum class Check {
	finite,      // any finite number
	positive,    // > 0
	nonnegative, // >= 0
	count,       // an integer >= 1
	natural,     // an integer >= 0
};

struct ParamSpec {
	const char *key;
	double def; // the default; NAN for an optional parameter without one
	Check check;
};

class Params {
public:
	// `who` prefixes messages ("pendulum 'left'").
	static Result<Params> parse(const std::string &who, std::span<const ParamSpec> specs,
				    const struct tcs_sim_model &model);

	// The value of a declared key: given, else its default (NAN if none).
	double operator[](std::string_view key) const;
	bool has(std::string_view key) const { return !std::isnan((*this)[key]); }

private:
	std::span<const ParamSpec> specs_;
	std::vector<double> values_;
};

} // namespace tcs::sim
