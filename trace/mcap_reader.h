// Reads an MCAP file (https://mcap.dev/spec) record by record from its start,
// as a streaming reader does, so that the trace of a run that was killed is
// read as far as its last complete record: a file cut short is not an error
// (truncated() says so), a file whose bytes are wrong is. Chunks are
// decompressed (zstd, or none) and CRC-checked. Every input is untrusted:
// lengths are checked before use, nothing is allocated from a length that
// the file does not hold, and errors are values naming the byte offset.
// Records are split, decoded and unpacked by mcap_records.h.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "error.h"
#include "mcap_records.h"

namespace tcs {

struct McapMessage {
	const McapChannel *channel = nullptr; // never null for a message returned
	const McapSchema *schema = nullptr;   // null when the channel has none
	uint32_t sequence = 0;
	uint64_t log_time = 0, publish_time = 0;
	std::string_view data; // valid until the next call to next()
};

class McapReader {
public:
	// Reads the whole file into memory. Errors: "PATH: No such file or
	// directory" (strerror), "PATH: not an MCAP file" (no magic).
	Status open(const std::string &path);
	// The same from bytes already in memory; name stands for the path in
	// messages (the fuzz target and the tests use it).
	Status open_bytes(std::string name, std::string bytes);

	// The next message in file order: true and *out filled; false at the
	// end of the data (the footer, or where a truncated file stops).
	// Errors: "PATH: at byte N: what is wrong".
	Result<bool> next(McapMessage *out);

	// After next() returned false: whether the file stopped before its
	// footer (a run killed mid-way), and how many bytes at its end were
	// not a complete record.
	bool truncated() const { return truncated_; }
	uint64_t bytes_unread() const { return bytes_unread_; }

	const std::map<uint16_t, McapChannel> &channels() const { return channels_; }
	const std::map<uint16_t, McapSchema> &schemas() const { return schemas_; }
	const std::string &profile() const { return profile_; }
	const std::string &library() const { return library_; }
	const std::string &name() const { return name_; }

private:
	Error error_at(uint64_t at, const std::string &what);
	bool whole_record(McapRecord *record);
	Result<bool> top_level(const McapRecord &record, McapMessage *out);
	Status footer();
	Status open_chunk(const McapRecord &record);
	Result<bool> next_in_chunk(McapMessage *out);
	std::string definition(const McapRecord &record);
	std::string message(std::string_view body, McapMessage *out);
	std::string_view records() const
	{
		return (records_in_buf_ ? unpacker_.buffer() : std::string_view(bytes_)).substr(records_off_, records_len_);
	}

	std::string name_, bytes_, profile_, library_;
	std::map<uint16_t, McapChannel> channels_;
	std::map<uint16_t, McapSchema> schemas_;
	// Each definition's bytes, to tell a repetition from a conflict.
	std::map<uint16_t, std::string> schema_records_, channel_records_;
	bool truncated_ = false;
	uint64_t bytes_unread_ = 0;

	std::optional<Error> error_; // sticky: next() repeats it
	size_t pos_ = 0;             // the next top-level record
	bool done_ = false;          // at the Footer, or where the file stops
	bool in_summary_ = false;    // past Data End
	// The records of the chunk being read: in the unpacker's buffer, or
	// in bytes_ when uncompressed (offsets, not a view, so that a copy of
	// the reader reads its own bytes); the chunk's offset for messages.
	bool records_in_buf_ = false;
	size_t records_off_ = 0, records_len_ = 0, records_pos_ = 0;
	uint64_t chunk_at_ = 0;
	McapChunkUnpacker unpacker_;
};

// Calls f on each message of reader (opened), in file order, up to f's first
// error. truncated, if given, says whether the file stopped before its
// footer.
Status for_each_message(McapReader &reader, const std::function<Status(const McapMessage &)> &f,
			bool *truncated = nullptr);
// The same for the MCAP file at path.
Status for_each_message(const std::string &path, const std::function<Status(const McapMessage &)> &f,
			bool *truncated = nullptr);

} // namespace tcs
