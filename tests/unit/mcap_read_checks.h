// What the reader's tests share: a reader's whole account of a file (its
// messages, error, truncation), files of known messages written by
// McapWriter, and where their records lie, found independently of the
// reader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mcap_writer.h"

namespace mcap_read_checks {

using tcs::McapCompression;
using tcs::McapWriter;

// A message as the reader returned it, or as the test wrote it.
struct Msg {
	uint16_t channel = 0;
	std::string topic, schema; // schema: its name, "" for none
	uint32_t seq = 0;
	uint64_t log = 0, pub = 0;
	std::string data;
	bool operator==(const Msg &) const = default;
};

// Everything one reader says about a file.
struct Outcome {
	bool opened = false;
	std::string error; // open's or next()'s, or ""
	std::vector<Msg> messages;
	bool truncated = false;
	uint64_t unread = 0;
};

// Reads all of bytes with a McapReader (the error sticks; the end stays
// the end).
Outcome read_bytes(const std::string &name, std::string bytes);
// The reader's error names both parts.
void expect_error(const Outcome &o, const std::string &part1, const std::string &part2 = "");
void expect_complete(const Outcome &o, size_t messages);

extern const char kClockSchema[];
extern const char kSliceSchema[];

// Four channels, one without a schema; deterministic JSON messages. Also
// what the writer says after each chunk: how many messages the chunks so
// far hold.
struct Sample {
	std::vector<Msg> expected;
	std::vector<size_t> messages_after_chunk;

	void write(McapWriter &w, int count);
};

// A file of count messages of s, in chunks of chunk_size bytes: its path.
std::string write_sample(const char *name, McapCompression compression, size_t chunk_size, int count, Sample &s);

// The top-level records of a file, found independently of the reader: where
// each ends, and where its Chunk records end.
struct Layout {
	std::vector<size_t> record_ends, chunk_ends;
	std::vector<size_t> chunk_starts;
};

Layout layout(const std::string &f);

} // namespace mcap_read_checks
