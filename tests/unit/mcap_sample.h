// What the writer's tests write: three channels of known JSON messages.
#pragma once

#include <cstdint>
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

} // namespace mcap_check
