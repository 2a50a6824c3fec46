// A clock of the coordinator's own process, in nanoseconds (the vDSO for
// the monotonic ones: no system call).
#pragma once

#include <time.h>

#include <cstdint>

#include "tcs/vtime.h"

namespace tcs {

inline int64_t clock_ns(clockid_t id)
{
	struct timespec ts;
	clock_gettime(id, &ts);
	return tcs_ts_to_ns(&ts);
}

} // namespace tcs
