// ODE's iterative stepper (dWorldQuickStep), repeatable per world: it
// reorders constraints with ODE's one process-wide random generator, so
// each world keeps its own generator state and runs its steps under it.
// The same world then moves the same way whatever other worlds step in
// between, and in whatever interleaving.
#pragma once

#include <ode/ode.h>

namespace tcs::sim {

class QuickStepper {
public:
	// dWorldQuickStep's result: 0 when ODE could not allocate its memory.
	int step(dWorldID world, double dt);

private:
	unsigned long seed_ = 0; // ODE's generator, as this world left it
};

} // namespace tcs::sim
