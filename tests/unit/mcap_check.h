// An MCAP file written by McapWriter, read back and checked against the
// MCAP specification: its messages and definitions as McapReader (the one
// reader) returns them, and what a streaming reader passes over (each
// chunk's layout, CRC and Message Indexes, Data End, the summary, Summary
// Offsets, the Footer), walked record by record with trace/'s decoders
// (mcap_records.h) and checked against the messages read. For the
// writer's tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mcap_records.h"

namespace mcap_check {

// A message as read, or as a test wrote it.
struct Msg {
	uint16_t channel;
	uint32_t seq;
	uint64_t log, pub;
	std::string data;
	bool operator==(const Msg &) const = default;
};

// A chunk as found in the data section, or as its Chunk Index describes it
// (which leaves messages 0).
struct ChunkInfo {
	uint64_t offset = 0, length = 0, start = 0, end = 0, usize = 0, csize = 0;
	std::string compression;
	std::map<uint16_t, uint64_t> mi_offsets; // channel -> its Message Index's offset
	uint64_t mi_length = 0;                  // of the Message Index records after it
	size_t messages = 0;
	bool operator==(const ChunkInfo &) const = default;
};

struct ReadBack {
	std::string error;     // the reader's error, or the first problem found
	bool complete = false; // Data End, summary, Footer and closing magic all there
	std::string profile, library;
	std::vector<Msg> messages;
	std::map<uint16_t, tcs::McapSchema> schemas; // defined in the data section
	std::map<uint16_t, tcs::McapChannel> channels;
	std::vector<ChunkInfo> chunks;            // complete ones
	std::vector<size_t> messages_after_chunk; // messages in chunks 0..i
	// The summary, for complete files.
	std::vector<tcs::McapSchema> summary_schemas;
	std::vector<tcs::McapChannel> summary_channels;
	std::vector<ChunkInfo> chunk_indexes;
	tcs::McapStatistics stats;
};

// The textbook bit-at-a-time CRC-32, independent of the writer's.
uint32_t ref_crc32(const void *data, size_t size);

// Everything the file holds, and the first problem with it.
ReadBack read_back(const std::string &file);
// The same, failing the test on a problem, or when the file is not
// complete as expected.
ReadBack read_back_ok(const std::string &file, bool complete);

// Fails the test unless the file's messages are the first `count` of want.
void expect_messages(const ReadBack &r, const std::vector<Msg> &want, size_t count);

} // namespace mcap_check
