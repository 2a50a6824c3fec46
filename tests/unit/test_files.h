// A folder for the files a test program writes: a temporary one, removed
// with its files at the end, or one named by an environment variable and
// kept (for another tool to read). Include after <cmocka.h>.
#pragma once

#include <string>
#include <string_view>

namespace test_files {

// Makes the folder: /tmp/PREFIX-XXXXXX, or $KEEP_ENV when that is set;
// false when it cannot.
bool test_dir_open(const char *prefix, const char *keep_env = nullptr);
// Removes the files and the folder, unless they are kept.
void test_dir_close();
// The folder.
const std::string &test_dir();
// A file in the folder, removed at the end.
std::string test_path(const std::string &name);

std::string slurp(const std::string &path);
void spit(const std::string &path, std::string_view bytes);

} // namespace test_files
