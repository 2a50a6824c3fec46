// The trace file writer: an MCAP file (https://mcap.dev/spec) of messages
// with their schemas, in chunks (zstd-compressed, or not), indexed for
// random access (docs/DESIGN.md §6).
//
// A chunk is compressed as it fills, a piece at a time (kFeedPiece bytes),
// so that no one write() stalls its caller for a whole chunk's compression.
//
// Every chunk is written with write(2) as soon as it is full, followed by its
// Message Index records, and is self-contained: the Schema and Channel
// records its messages need are repeated inside it. A run killed at any point
// therefore leaves a file whose complete chunks a streaming reader can still
// decode; close() adds the summary (Schemas, Channels, Statistics, Chunk
// Indexes, Summary Offsets) and the Footer that indexed readers start from.
//
// Runs on one thread (the coordinator's); not thread-safe. The per-message
// path reuses its buffers and does not allocate once they have grown.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "error.h"
#include "unique_fd.h"

struct ZSTD_CCtx_s;
struct iovec;

namespace tcs {

enum class McapCompression { none, zstd };

// An allocator whose vectors grow without zeroing what they add (resize()
// default-initialises bytes: leaves them as they are), for the chunk, into
// which each message is then copied.
template <class T> struct GrowUninitialised : std::allocator<T> {
	template <class U> struct rebind {
		using other = GrowUninitialised<U>;
	};
	GrowUninitialised() = default;
	template <class U> GrowUninitialised(const GrowUninitialised<U> &) noexcept {}
	template <class U> void construct(U *p) noexcept(std::is_nothrow_default_constructible_v<U>)
	{
		::new (static_cast<void *>(p)) U;
	}
	template <class U, class... Args> void construct(U *p, Args &&...args)
	{
		::new (static_cast<void *>(p)) U(std::forward<Args>(args)...);
	}
};

struct McapWriterOptions {
	// A chunk is closed and written once its uncompressed records reach
	// this many bytes (a single larger message makes a larger chunk).
	size_t chunk_size = 1 << 20;
	McapCompression compression = McapCompression::zstd;
	int zstd_level = 3;
};

class McapWriter {
public:
	using Metadata = std::map<std::string, std::string>;

	explicit McapWriter(McapWriterOptions options = {});
	// Closes the file if it is still open; the error, if any, is lost:
	// call close() to see it.
	~McapWriter();
	McapWriter(const McapWriter &) = delete;
	McapWriter &operator=(const McapWriter &) = delete;

	// Creates (or truncates) path and writes the magic and the Header.
	// profile is MCAP's well-known profile name ("" for none); library
	// names the writer, for whoever debugs the file.
	Status open(const std::string &path, std::string_view profile = "", std::string_view library = "tcs");

	// Registers a schema; returns its id (1, 2, ...). Registering the
	// same name, encoding and data again returns the same id.
	Result<uint16_t> add_schema(std::string_view name, std::string_view encoding, std::string_view data);
	// A JSON Schema (encoding "jsonschema").
	Result<uint16_t> add_schema(std::string_view name, std::string_view json_schema)
	{
		return add_schema(name, "jsonschema", json_schema);
	}

	// Registers a channel; returns its id (0, 1, ...). schema_id is an id
	// from add_schema, or 0 for none.
	Result<uint16_t> add_channel(std::string_view topic, std::string_view message_encoding, uint16_t schema_id,
				     const Metadata &metadata = {});
	// A channel of JSON messages (message encoding "json").
	Result<uint16_t> add_channel(std::string_view topic, uint16_t schema_id, const Metadata &metadata = {})
	{
		return add_channel(topic, "json", schema_id, metadata);
	}

	// Appends one message to the current chunk, writing the chunk out when
	// it is full. Messages get a per-channel sequence number 0, 1, ...
	// Log times need not be in order.
	Status write(uint16_t channel_id, uint64_t log_time_ns, uint64_t publish_time_ns, const void *data,
		     size_t size);
	Status write(uint16_t channel_id, uint64_t log_time_ns, uint64_t publish_time_ns, std::string_view data)
	{
		return write(channel_id, log_time_ns, publish_time_ns, data.data(), data.size());
	}

	// Writes the current chunk out now, however small (a no-op when it is
	// empty): what was written so far survives a crash from here on.
	Status flush();

	// Writes the last chunk, the summary, the Footer and the closing magic,
	// and closes the file. After an earlier error it only closes the file
	// and returns that error again.
	Status close();

	bool is_open() const { return fd_.get() >= 0; }
	const std::string &path() const { return path_; }
	uint64_t message_count() const { return message_count_; }
	uint32_t chunk_count() const { return chunk_count_; }
	// Bytes in the file so far, and in the chunk not yet written.
	uint64_t file_bytes() const { return offset_; }
	size_t pending_bytes() const { return chunk_.size(); }

private:
	// As a Message Index record lays its entries out (mcap_writer.cc
	// copies them whole).
	struct IndexEntry {
		uint64_t log_time;
		uint64_t offset; // in the uncompressed chunk
	};
	static_assert(sizeof(IndexEntry) == 16);
	struct Schema {
		std::string name, encoding, data;
		uint64_t in_chunk = 0; // the chunk generation it was last written into
	};
	struct Channel {
		std::string topic, message_encoding;
		uint16_t schema_id = 0;
		Metadata metadata;
		uint64_t in_chunk = 0;
		uint32_t sequence = 0;
		uint64_t message_count = 0;
		// This chunk's messages on the channel, and whether their log
		// times came out of order.
		std::vector<IndexEntry> index;
		bool unsorted = false;
	};

	Error set_error(const std::string &what, int err);
	Status failed_status() const;
	Status write_all(const ::iovec *iov, int count);
	Status feed(int directive);
	void restart_chunk(); // empty, nothing fed
	Status finish_chunk();
	void reset_state();

	McapWriterOptions options_;
	ZSTD_CCtx_s *zstd_ = nullptr;
	UniqueFd fd_;
	std::string path_;
	std::optional<Error> error_; // sticky: the file is not trusted after it

	std::vector<Schema> schemas_;   // id i + 1
	std::vector<Channel> channels_; // id i

	uint64_t offset_ = 0;   // bytes written to the file
	uint32_t data_crc_ = 0; // of the data section so far
	uint64_t message_count_ = 0;
	uint64_t start_time_ = UINT64_MAX, end_time_ = 0;
	uint32_t chunk_count_ = 0;

	// The chunk being filled, and how much of it was fed to the CRC and
	// the compressor, whose output so far is compressed_[0, zpos_).
	uint64_t chunk_gen_ = 1;
	std::vector<uint8_t, GrowUninitialised<uint8_t>> chunk_;
	size_t fed_ = 0;
	uint32_t chunk_crc_ = 0;
	size_t zpos_ = 0;
	std::vector<uint16_t> chunk_channels_; // channels with messages in it
	uint64_t chunk_start_time_ = UINT64_MAX, chunk_end_time_ = 0;

	// Reused from chunk to chunk.
	std::vector<uint8_t> compressed_;
	std::vector<uint8_t> chunk_head_;
	std::vector<uint8_t> message_indexes_;

	// The summary's Chunk Index records, serialised as chunks are written.
	std::vector<uint8_t> chunk_index_records_;
};

} // namespace tcs
