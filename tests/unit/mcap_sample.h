// What the writer's tests write, and where: three channels of known JSON
// messages, and the folder their files go to (a temporary one, removed at
// the end, or TCS_MCAP_TEST_DIR, kept, for tests/mcap/check.mjs to read
// with the reference TypeScript readers).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mcap_check.h"
#include "mcap_writer.h"

namespace mcap_check {

extern const char kSliceSchema[];
extern const char kClockSchema[];

// Three channels, two sharing a schema, and deterministic JSON messages of
// varying sizes on them. The writer numbers each channel's messages; so
// does the expectation.
struct Sample {
	uint16_t ch[3];
	uint32_t seq[3] = { 0, 0, 0 };
	std::vector<Msg> expected;

	void setup(tcs::McapWriter &w);
	// Message i (call in order of i).
	Msg next(int i);
	// Writes messages from..to-1, and expects them.
	void write(tcs::McapWriter &w, int from, int to);
};

// Makes the folder (prefix names a temporary one); false when it cannot.
bool test_dir_open(const char *prefix);
// Removes the files and the folder, unless they are to be kept.
void test_dir_close();
// A file in the folder, removed at the end.
std::string test_path(const std::string &name);

std::string slurp(const std::string &path);
void spit(const std::string &path, std::string_view bytes);

} // namespace mcap_check
