// dWorldQuickStep under a world's own state of ODE's random generator.
#include "quick_step.h"

#include <mutex>

namespace tcs::sim {

namespace {

// dRandGetSeed/dRandSetSeed are one process-wide variable.
std::mutex ode_rand_lock;

} // namespace

int QuickStepper::step(dWorldID world, double dt)
{
	std::lock_guard<std::mutex> g(ode_rand_lock);
	unsigned long saved = dRandGetSeed();
	dRandSetSeed(seed_);
	int ok = dWorldQuickStep(world, dt);
	seed_ = dRandGetSeed();
	dRandSetSeed(saved);
	return ok;
}

} // namespace tcs::sim
