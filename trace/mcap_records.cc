// The MCAP records decoded field by field, and Chunks unpacked (see
// mcap_records.h): all of the format's byte layout a reader needs.
#include "mcap_records.h"
#include "mcap_crc32.h"
#include "mcap_format.h"

#include <zstd.h>

#include <cstdio>

namespace tcs {

namespace {

// A chunk larger than this is refused rather than allocated: tcs writes
// 1 MiB chunks, and a huge size is far more likely damage than data.
constexpr uint64_t kMaxChunkBytes = uint64_t(1) << 30;
// No zstd frame expands by more than this: a block holds at most 128 KiB
// and the smallest block (RLE) takes 4 bytes. A declared size beyond it is
// a lie the allocation must not believe.
constexpr uint64_t kMaxZstdRatio = 32768;

// Bounds-checked little-endian fields of one record whose bytes are all
// there; any overrun clears ok() and yields zeros.
class Fields {
public:
	explicit Fields(std::string_view s) : s_(s) {}
	bool ok() const { return ok_; }
	size_t used() const { return pos_; }
	size_t left() const { return s_.size() - pos_; }

	uint64_t le(size_t k)
	{
		if (!ok_ || left() < k) {
			ok_ = false;
			return 0;
		}
		uint64_t v = 0;
		for (size_t i = 0; i < k; i++)
			v |= uint64_t(uint8_t(s_[pos_ + i])) << (8 * i);
		pos_ += k;
		return v;
	}
	uint8_t u8() { return uint8_t(le(1)); }
	uint16_t u16() { return uint16_t(le(2)); }
	uint32_t u32() { return uint32_t(le(4)); }
	uint64_t u64() { return le(8); }
	std::string_view bytes(uint64_t k)
	{
		if (!ok_ || left() < k) {
			ok_ = false;
			return {};
		}
		std::string_view v = s_.substr(pos_, size_t(k));
		pos_ += size_t(k);
		return v;
	}
	std::string_view str() { return bytes(u32()); }

private:
	std::string_view s_;
	size_t pos_ = 0;
	bool ok_ = true;
};

// What the decoders return once the fields are read: "" or the overrun.
std::string done(const Fields &f, std::string_view body, const char *what, size_t *known, const char *fields = "fields")
{
	if (!f.ok())
		return std::string("the ") + what + "'s " + fields + " run past its " + std::to_string(body.size()) + " bytes";
	if (known)
		*known = f.used();
	return "";
}

// An array of entries of `entry` bytes each, prefixed with its byte length.
bool array_of(Fields &f, size_t entry, Fields *array)
{
	const uint32_t bytes = f.u32();
	*array = Fields(f.bytes(bytes));
	return f.ok() && bytes % entry == 0;
}

std::string hex32(uint32_t v)
{
	char buf[16];
	snprintf(buf, sizeof buf, "0x%08x", v);
	return buf;
}

} // namespace

std::string printable(std::string_view s)
{
	std::string out;
	for (char c : s.substr(0, 40))
		out += c >= 0x20 && c < 0x7F ? c : '?';
	return s.size() > 40 ? out + "..." : out;
}

bool mcap_record_at(std::string_view bytes, uint64_t offset, McapRecord *out)
{
	if (offset > bytes.size())
		return false;
	Fields head(bytes.substr(size_t(offset)));
	const uint8_t op = head.u8();
	const uint64_t len = head.u64();
	if (!head.ok() || len > head.left())
		return false;
	out->op = op;
	out->offset = offset;
	out->body = bytes.substr(size_t(offset) + kMcapRecordHead, size_t(len));
	return true;
}

std::string mcap_decode_header(std::string_view body, McapHeader *out, size_t *known)
{
	Fields f(body);
	out->profile = f.str();
	out->library = f.str();
	return done(f, body, "Header", known, "strings");
}

std::string mcap_decode_schema(std::string_view body, McapSchema *out, size_t *known)
{
	Fields f(body);
	out->id = f.u16();
	out->name = f.str();
	out->encoding = f.str();
	out->data = f.str();
	std::string what = done(f, body, "Schema", known);
	if (what.empty() && out->id == 0)
		return "a Schema with id 0, which means \"no schema\"";
	return what;
}

std::string mcap_decode_channel(std::string_view body, McapChannel *out, size_t *known)
{
	Fields f(body);
	out->id = f.u16();
	out->schema_id = f.u16();
	out->topic = f.str();
	out->message_encoding = f.str();
	Fields metadata(f.str());
	if (std::string what = done(f, body, "Channel", known); !what.empty())
		return what;
	out->metadata.clear();
	while (metadata.ok() && metadata.left() > 0) {
		std::string key(metadata.str());
		out->metadata[key] = metadata.str();
	}
	if (!metadata.ok())
		return "the metadata of Channel " + std::to_string(out->id) + " is malformed";
	return "";
}

std::string mcap_decode_message(std::string_view body, McapMessageFields *out)
{
	Fields f(body);
	out->channel_id = f.u16();
	out->sequence = f.u32();
	out->log_time = f.u64();
	out->publish_time = f.u64();
	if (!f.ok())
		return "a Message of " + std::to_string(body.size()) + " bytes, shorter than its fixed fields";
	out->data = body.substr(f.used());
	return "";
}

std::string mcap_decode_chunk(std::string_view body, McapChunk *out, size_t *known)
{
	Fields f(body);
	out->message_start_time = f.u64();
	out->message_end_time = f.u64();
	out->uncompressed_size = f.u64();
	out->uncompressed_crc = f.u32();
	out->compression = f.str();
	out->records = f.bytes(f.u64());
	return done(f, body, "Chunk", known);
}

std::string mcap_decode_message_index(std::string_view body, McapMessageIndex *out, size_t *known)
{
	Fields f(body), entries(std::string_view{});
	out->channel_id = f.u16();
	bool whole = array_of(f, 16, &entries);
	if (std::string what = done(f, body, "Message Index", known); !what.empty())
		return what;
	if (!whole)
		return "the Message Index's records are not 16 bytes each";
	out->records.clear();
	while (entries.left() > 0) {
		uint64_t log_time = entries.u64();
		out->records.emplace_back(log_time, entries.u64());
	}
	return "";
}

std::string mcap_decode_chunk_index(std::string_view body, McapChunkIndex *out, size_t *known)
{
	Fields f(body), offsets(std::string_view{});
	out->message_start_time = f.u64();
	out->message_end_time = f.u64();
	out->chunk_start_offset = f.u64();
	out->chunk_length = f.u64();
	bool whole = array_of(f, 2 + 8, &offsets);
	out->message_index_length = f.u64();
	out->compression = f.str();
	out->compressed_size = f.u64();
	out->uncompressed_size = f.u64();
	if (std::string what = done(f, body, "Chunk Index", known); !what.empty())
		return what;
	if (!whole)
		return "the Chunk Index's message index offsets are not 10 bytes each";
	out->message_index_offsets.clear();
	while (offsets.left() > 0) {
		uint16_t channel = offsets.u16();
		out->message_index_offsets[channel] = offsets.u64();
	}
	return "";
}

std::string mcap_decode_statistics(std::string_view body, McapStatistics *out, size_t *known)
{
	Fields f(body), counts(std::string_view{});
	out->message_count = f.u64();
	out->schema_count = f.u16();
	out->channel_count = f.u32();
	out->attachment_count = f.u32();
	out->metadata_count = f.u32();
	out->chunk_count = f.u32();
	out->message_start_time = f.u64();
	out->message_end_time = f.u64();
	bool whole = array_of(f, 2 + 8, &counts);
	if (std::string what = done(f, body, "Statistics", known); !what.empty())
		return what;
	if (!whole)
		return "the Statistics' channel message counts are not 10 bytes each";
	out->channel_message_counts.clear();
	while (counts.left() > 0) {
		uint16_t channel = counts.u16();
		out->channel_message_counts[channel] = counts.u64();
	}
	return "";
}

std::string mcap_decode_summary_offset(std::string_view body, McapSummaryOffset *out, size_t *known)
{
	Fields f(body);
	out->group_opcode = f.u8();
	out->group_start = f.u64();
	out->group_length = f.u64();
	return done(f, body, "Summary Offset", known);
}

std::string mcap_decode_footer(std::string_view body, McapFooter *out, size_t *known)
{
	Fields f(body);
	out->summary_start = f.u64();
	out->summary_offset_start = f.u64();
	out->summary_crc = f.u32();
	return done(f, body, "Footer", known);
}

std::string mcap_decode_data_end(std::string_view body, uint32_t *data_section_crc, size_t *known)
{
	Fields f(body);
	*data_section_crc = f.u32();
	return done(f, body, "Data End", known);
}

McapChunkUnpacker::~McapChunkUnpacker() { ZSTD_freeDCtx(dctx_); }

std::string McapChunkUnpacker::unpack(const McapChunk &chunk, std::string_view *records)
{
	const uint64_t size = chunk.uncompressed_size;
	const std::string_view stored = chunk.records;
	if (size > kMaxChunkBytes)
		return "the Chunk declares " + std::to_string(size) +
		       " uncompressed bytes, more than the 1 GiB this reader accepts";
	if (chunk.compression.empty()) {
		if (stored.size() != size)
			return "the uncompressed Chunk holds " + std::to_string(stored.size()) +
			       " bytes of records but declares " + std::to_string(size);
		*records = stored;
	} else if (chunk.compression == "zstd") {
		if (size > stored.size() * kMaxZstdRatio)
			return "the Chunk declares " + std::to_string(size) + " uncompressed bytes, more than " +
			       std::to_string(stored.size()) + " bytes of zstd data can hold";
		if (size > 0 || !stored.empty()) {
			// The frame states its size too: a mismatch is damage,
			// found before allocating anything.
			unsigned long long frame = ZSTD_getFrameContentSize(stored.data(), stored.size());
			if (frame == ZSTD_CONTENTSIZE_ERROR)
				return "the Chunk's records are not a zstd frame";
			if (frame != ZSTD_CONTENTSIZE_UNKNOWN && frame != size)
				return "the Chunk's zstd frame holds " + std::to_string(frame) +
				       " bytes but the Chunk declares " + std::to_string(size);
			if (buf_.size() < size)
				buf_.resize(size_t(size));
			if (!dctx_ && !(dctx_ = ZSTD_createDCtx()))
				return "cannot create a zstd decompression context";
			size_t n = ZSTD_decompressDCtx(dctx_, buf_.data(), size_t(size), stored.data(), stored.size());
			if (ZSTD_isError(n))
				return std::string("the Chunk's zstd data is damaged: ") + ZSTD_getErrorName(n);
			if (n != size)
				return "the Chunk's zstd data decompresses to " + std::to_string(n) +
				       " bytes but the Chunk declares " + std::to_string(size);
		}
		*records = std::string_view(buf_).substr(0, size_t(size));
	} else if (chunk.compression == "lz4") {
		return "the Chunk is lz4-compressed: lz4 chunks are not supported (only zstd and none)";
	} else {
		return "the Chunk's compression '" + printable(chunk.compression) + "' is unknown";
	}
	// A CRC of 0 means the writer did not compute one.
	if (chunk.uncompressed_crc != 0) {
		uint32_t got = mcap_crc32(0, records->data(), records->size());
		if (got != chunk.uncompressed_crc)
			return "the CRC of the Chunk's records is " + hex32(got) + ", the Chunk says " +
			       hex32(chunk.uncompressed_crc);
	}
	return "";
}

} // namespace tcs
