// Reading a whole file into memory, for the inputs tcs parses (scenarios,
// traces): errors name the path; a limit keeps a wrong file from filling
// memory.
#pragma once

#include <cstddef>
#include <string>

#include "error.h"

namespace tcs {

// The bytes of path. Errors: "PATH: strerror", and "PATH: larger than
// LIMIT bytes" once it has read more than limit.
Result<std::string> read_file(const std::string &path, size_t limit);

} // namespace tcs
