// Where libtcs_preload.so is: beside tcs-run in the build tree, or at the
// installed location relative to tcs-run's own directory, so that an
// installation into any prefix works without configuration.
#pragma once

#include <string>

#include "error.h"

namespace tcs {

Result<std::string> find_preload();

} // namespace tcs
