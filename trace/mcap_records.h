// The records of an MCAP file (https://mcap.dev/spec) one at a time: where
// each lies, each kind's fields, and a Chunk's records unpacked. McapReader
// reads messages with them; they are public for whoever must also see what
// a streaming reader passes over (the Message Indexes, the summary, the
// Footer), as the writer's tests do. Every input is untrusted: a length is
// checked against the bytes there before it is used, and nothing is
// allocated from a length the bytes do not hold.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

struct ZSTD_DCtx_s;

namespace tcs {

// A record whose bytes are all there.
struct McapRecord {
	uint8_t op = 0;        // an McapOpcode, or one of a later version
	uint64_t offset = 0;   // of its opcode, in the bytes it was found in
	std::string_view body; // its content
};

// The record at offset of bytes (a file, or a Chunk's records): false when
// they end before all of it.
bool mcap_record_at(std::string_view bytes, uint64_t offset, McapRecord *out);

// Each record's fields, as the specification names them. Views point into
// the record's body.
struct McapHeader {
	std::string_view profile, library;
};

struct McapSchema {
	uint16_t id = 0;
	std::string name, encoding, data;
	bool operator==(const McapSchema &) const = default;
};

struct McapChannel {
	uint16_t id = 0;
	std::string topic, message_encoding;
	uint16_t schema_id = 0; // 0: none
	std::map<std::string, std::string> metadata;
	bool operator==(const McapChannel &) const = default;
};

struct McapMessageFields {
	uint16_t channel_id = 0;
	uint32_t sequence = 0;
	uint64_t log_time = 0, publish_time = 0;
	std::string_view data;
};

struct McapChunk {
	uint64_t message_start_time = 0, message_end_time = 0;
	uint64_t uncompressed_size = 0;
	uint32_t uncompressed_crc = 0; // 0: not computed
	std::string_view compression;  // "zstd", or "" for none
	std::string_view records;      // as stored (compressed or not)
};

struct McapMessageIndex {
	uint16_t channel_id = 0;
	// (log time, offset of the Message in the Chunk's uncompressed records)
	std::vector<std::pair<uint64_t, uint64_t>> records;
};

struct McapChunkIndex {
	uint64_t message_start_time = 0, message_end_time = 0;
	uint64_t chunk_start_offset = 0, chunk_length = 0;
	std::map<uint16_t, uint64_t> message_index_offsets; // channel -> file offset
	uint64_t message_index_length = 0;
	std::string_view compression;
	uint64_t compressed_size = 0, uncompressed_size = 0;
};

struct McapStatistics {
	uint64_t message_count = 0;
	uint16_t schema_count = 0;
	uint32_t channel_count = 0, attachment_count = 0, metadata_count = 0, chunk_count = 0;
	uint64_t message_start_time = 0, message_end_time = 0;
	std::map<uint16_t, uint64_t> channel_message_counts;
	bool operator==(const McapStatistics &) const = default;
};

struct McapSummaryOffset {
	uint8_t group_opcode = 0;
	uint64_t group_start = 0, group_length = 0;
};

struct McapFooter {
	uint64_t summary_start = 0, summary_offset_start = 0; // 0: none
	uint32_t summary_crc = 0;                             // 0: not computed
};

// The decoders: "" when body holds the record's fields, else what is wrong
// ("the Chunk's fields run past its 12 bytes"), for the caller to say
// where. Bytes after the fields are allowed: later versions of the format
// may append fields. *known, when asked for, is how many bytes the fields
// took: a definition's repeat is compared on those, and a writer's test
// checks that nothing follows them. A Message's data is the rest of it.
std::string mcap_decode_header(std::string_view body, McapHeader *out, size_t *known = nullptr);
std::string mcap_decode_schema(std::string_view body, McapSchema *out, size_t *known = nullptr);
std::string mcap_decode_channel(std::string_view body, McapChannel *out, size_t *known = nullptr);
std::string mcap_decode_message(std::string_view body, McapMessageFields *out);
std::string mcap_decode_chunk(std::string_view body, McapChunk *out, size_t *known = nullptr);
std::string mcap_decode_message_index(std::string_view body, McapMessageIndex *out, size_t *known = nullptr);
std::string mcap_decode_chunk_index(std::string_view body, McapChunkIndex *out, size_t *known = nullptr);
std::string mcap_decode_statistics(std::string_view body, McapStatistics *out, size_t *known = nullptr);
std::string mcap_decode_summary_offset(std::string_view body, McapSummaryOffset *out, size_t *known = nullptr);
std::string mcap_decode_footer(std::string_view body, McapFooter *out, size_t *known = nullptr);
std::string mcap_decode_data_end(std::string_view body, uint32_t *data_section_crc, size_t *known = nullptr);

// A string from a file (a name, an encoding), fit to quote in a one-line
// message: its first 40 bytes, each not printable ASCII as '?'.
std::string printable(std::string_view s);

// Unpacks Chunks: decompressed (zstd, or none) and CRC-checked. Holds the
// buffer the records are decompressed into, and zstd's context, made once
// (making one per chunk costs more than decompressing a small chunk); a
// copy makes its own.
class McapChunkUnpacker {
public:
	McapChunkUnpacker() = default;
	McapChunkUnpacker(const McapChunkUnpacker &other) : buf_(other.buf_) {}
	McapChunkUnpacker &operator=(const McapChunkUnpacker &other)
	{
		buf_ = other.buf_;
		return *this;
	}
	~McapChunkUnpacker();

	// "" and *records, the chunk's uncompressed records: chunk.records
	// itself when uncompressed, else this unpacker's buffer (valid until
	// the next unpack); or what is wrong with the chunk.
	std::string unpack(const McapChunk &chunk, std::string_view *records);
	// The buffer compressed chunks are unpacked into (a copy of a reader
	// finds its chunk's records there by offset).
	std::string_view buffer() const { return buf_; }

private:
	std::string buf_; // only grows: reused by every chunk
	ZSTD_DCtx_s *dctx_ = nullptr;
};

} // namespace tcs
