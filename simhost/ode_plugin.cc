// The built-in ODE plug-in: the C table of the simulation ABI. The only
// place where C++ meets the C boundary, so the only place that catches
// (allocation failures are the only exceptions below) and turns an Error
// into the caller's err buffer.
#include <cstdio>
#include <new>

#include "tcs/simhost.h"
#include "world.h"

namespace {

using tcs::sim::World;

// The ABI's opaque tcs_sim is our World, never defined as a type of its
// own: a plug-in loaded beside us may define one, and two definitions with
// inline members would clash in the process.
World *W(tcs_sim *sim)
{
	return reinterpret_cast<World *>(sim);
}

const World *W(const tcs_sim *sim)
{
	return reinterpret_cast<const World *>(sim);
}

void set_err(char *err, size_t errlen, const std::string &msg)
{
	if (err && errlen > 0)
		snprintf(err, errlen, "%s", msg.c_str());
}

tcs_sim *create(const struct tcs_sim_model *models, size_t nmodels, int64_t step_ns, char *err, size_t errlen)
{
	try {
		auto w = World::create(models, nmodels, step_ns);
		if (!w) {
			set_err(err, errlen, w.error().message);
			return nullptr;
		}
		return reinterpret_cast<tcs_sim *>(w->release());
	} catch (const std::bad_alloc &) {
		set_err(err, errlen, "out of memory creating the world");
	} catch (...) {
		set_err(err, errlen, "internal error creating the world");
	}
	return nullptr;
}

int step(tcs_sim *sim, char *err, size_t errlen)
{
	if (!sim) {
		set_err(err, errlen, "no world");
		return -1;
	}
	try {
		if (auto s = W(sim)->step(); !s) {
			set_err(err, errlen, s.error().message);
			return -1;
		}
		return 0;
	} catch (const std::bad_alloc &) {
		set_err(err, errlen, "out of memory in a step");
	} catch (...) {
		set_err(err, errlen, "internal error in a step");
	}
	return -1;
}

size_t signal_count(const tcs_sim *sim)
{
	return sim ? W(sim)->signal_count() : 0;
}

const struct tcs_sim_signal_info *signal_info(const tcs_sim *sim, size_t index)
{
	return sim ? W(sim)->signal_info(index) : nullptr;
}

int read(const tcs_sim *sim, size_t index, double *out)
{
	return sim ? W(sim)->read(index, out) : -1;
}

int write(tcs_sim *sim, size_t index, const double *values)
{
	return sim ? W(sim)->write(index, values) : -1;
}

void destroy(tcs_sim *sim)
{
	delete W(sim);
}

int64_t file_step_ns(const tcs_sim *sim)
{
	return sim ? W(sim)->file_step_ns() : 0;
}

const struct tcs_simhost_plugin plugin = {
	TCS_SIMHOST_ABI_VERSION,
	"ode",
	tcs::sim::kModelTypeNames,
	create,
	step,
	signal_count,
	signal_info,
	read,
	write,
	destroy,
	file_step_ns,
};

} // namespace

extern "C" const struct tcs_simhost_plugin *tcs_simhost_ode_plugin(void)
{
	return &plugin;
}
