// Parsing and checking of model parameters against a model's table.
#include "params.h"

#include <cassert>
#include <cstdio>

namespace tcs::sim {

namespace {

std::string num(double v)
{
	char buf[32];
	snprintf(buf, sizeof buf, "%g", v);
	return buf;
}

bool is_integer(double v)
{
	// 2^53: beyond it, doubles skip integers and a seed would be ambiguous.
	return v == std::floor(v) && std::fabs(v) <= 9007199254740992.0;
}

// nullptr when v passes the check, else what it must be.
const char *violation(Check check, double v)
{
	switch (check) {
	case Check::finite:
		return nullptr;
	case Check::positive:
		return v > 0 ? nullptr : "must be > 0";
	case Check::nonnegative:
		return v >= 0 ? nullptr : "must be >= 0";
	case Check::count:
		return is_integer(v) && v >= 1 ? nullptr : "must be an integer >= 1";
	case Check::natural:
		return is_integer(v) && v >= 0 ? nullptr : "must be an integer >= 0";
	}
	return nullptr;
}

std::string known_keys(std::span<const ParamSpec> specs)
{
	std::string s;
	for (const ParamSpec &p : specs) {
		if (!s.empty())
			s += ", ";
		s += p.key;
	}
	return s;
}

} // namespace

Result<Params> Params::parse(const std::string &who, std::span<const ParamSpec> specs,
			     const struct tcs_sim_model &model)
{
	Params out;
	out.specs_ = specs;
	out.values_.reserve(specs.size());
	for (const ParamSpec &p : specs)
		out.values_.push_back(p.def);
	std::vector<bool> given(specs.size(), false);

	if (model.nparams > 0 && (!model.param_keys || !model.param_values))
		return Error{ who + ": parameters given without keys or values" };
	for (size_t i = 0; i < model.nparams; i++) {
		const char *key = model.param_keys[i];
		if (!key)
			return Error{ who + ": parameter " + std::to_string(i) + " has no name" };
		size_t k = 0;
		while (k < specs.size() && std::string_view(specs[k].key) != key)
			k++;
		if (k == specs.size())
			return Error{ who + ": unknown parameter '" + key + "' (known: " + known_keys(specs) + ")" };
		if (given[k])
			return Error{ who + ": parameter '" + key + "' given twice" };
		double v = model.param_values[i];
		if (!std::isfinite(v))
			return Error{ who + ": parameter '" + key + "' must be a finite number (got " + num(v) + ")" };
		if (const char *why = violation(specs[k].check, v))
			return Error{ who + ": parameter '" + key + "' " + why + " (got " + num(v) + ")" };
		given[k] = true;
		out.values_[k] = v;
	}
	return out;
}

double Params::operator[](std::string_view key) const
{
	for (size_t k = 0; k < specs_.size(); k++)
		if (specs_[k].key == key)
			return values_[k];
	assert(!"a model asked for a parameter it did not declare");
	return NAN;
}

} // namespace tcs::sim
