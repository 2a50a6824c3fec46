// The options tcs-run and coordinatord share about a run (run_options.h).
#include "run_options.h"

#include "cli_numbers.h"
#include "cli_time.h"

namespace tcs {

std::string run_option_of(const struct option *longopts, int opt)
{
	for (const struct option *o = longopts; o->name; o++) {
		std::string name = o->name;
		if (o->val == opt && (name == "mode" || name == "epoch" || name == "no-slack" || name == "spin-cost" ||
				      name == "seed"))
			return name;
	}
	return "";
}

Status set_run_option(const std::string &name, const std::string &arg, CoordinatorConfig &cfg)
{
	auto fail = [&name](const std::string &why) { return Error{ "--" + name + ": " + why }; };
	if (name == "mode") {
		if (arg == "cpu" || arg == "lockstep") {
			cfg.mode = arg == "cpu" ? TCS_MODE_CPU : TCS_MODE_LOCKSTEP;
			return Ok{};
		}
		return fail("'" + arg + "' is not a mode (cpu or lockstep)");
	}
	if (name == "epoch") {
		auto v = parse_epoch(arg);
		if (!v)
			return fail(v.error().message);
		cfg.epoch_ns = *v;
	} else if (name == "no-slack") {
		cfg.slack = false;
	} else if (name == "spin-cost") {
		auto v = parse_duration_pair(arg, kMostSpinCost);
		if (!v)
			return fail(v.error().message);
		cfg.spin_costs = SpinCosts{ v->first, v->second };
	} else if (name == "seed") {
		auto v = parse_unsigned(arg);
		if (!v)
			return fail(v.error().message);
		cfg.seed = *v;
	}
	return Ok{};
}

} // namespace tcs
