// ODE's one-time initialisation. dInitODE2 must run exactly once and before
// anything else; a collision-using thread must also have its own ODE data
// (in builds with thread-local storage), so each thread allocates it on its
// first call.
#include "ode_init.h"

#include <mutex>

#include <ode/ode.h>

namespace tcs::sim {

Status ode_ready()
{
	static std::once_flag once;
	static bool init_ok;
	std::call_once(once, [] { init_ok = dInitODE2(0) != 0; });
	if (!init_ok)
		return Error{ "ODE: dInitODE2 failed" };

	thread_local bool thread_ok;
	if (!thread_ok) {
		if (dAllocateODEDataForThread(dAllocateMaskAll) == 0)
			return Error{ "ODE: could not allocate its per-thread data" };
		thread_ok = true;
	}
	return Ok{};
}

} // namespace tcs::sim
