// The MCAP writer (see mcap_writer.h): what goes into each chunk, when it
// is written out with its indexes, and the summary that closes the file.
// How each record is laid out is mcap_encode.h's.
#include "mcap_writer.h"
#include "mcap_crc32.h"
#include "mcap_encode.h"

#include <fcntl.h>
#include <sys/uio.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <climits>
#include <cstring>

namespace tcs {

using namespace mcap_encode;

namespace {

static_assert(std::endian::native == std::endian::little, "the writer stores native integers as MCAP's little-endian");

// McapOpcode, content length, channel id, sequence, log time, publish time.
constexpr size_t kMessageHead = 1 + 8 + 2 + 4 + 8 + 8;

bool fits_u32(size_t n) { return uint64_t(n) <= UINT32_MAX; }

// Bytes of a chunk compressed at a time: some 15 us of zstd's level 1 on
// JSON, the longest a write() of a small message takes (the coordinator
// writes between requests: docs/PERFORMANCE.md). Each piece ends a zstd
// block; the chunk stays one frame, its history kept.
constexpr size_t kFeedPiece = 8192;

} // namespace

McapWriter::McapWriter(McapWriterOptions options) : options_(options) {}

McapWriter::~McapWriter()
{
	if (is_open())
		(void)close();
	ZSTD_freeCCtx(zstd_);
}

Error McapWriter::set_error(const std::string &what, int err)
{
	error_ = Error{ path_ + ": " + what + ": " + std::strerror(err) };
	return *error_;
}

// The error to return when no file is open (before open(), after close()),
// or the sticky one.
Status McapWriter::failed_status() const
{
	if (error_)
		return *error_;
	if (!is_open())
		return Error{ "MCAP writer: no file is open" + (path_.empty() ? std::string() : " (" + path_ + " was closed)") };
	return Ok{};
}

void McapWriter::reset_state()
{
	error_.reset();
	schemas_.clear();
	channels_.clear();
	offset_ = 0;
	data_crc_ = 0;
	message_count_ = 0;
	start_time_ = UINT64_MAX;
	end_time_ = 0;
	chunk_count_ = 0;
	chunk_gen_ = 1;
	restart_chunk();
	chunk_channels_.clear();
	chunk_start_time_ = UINT64_MAX;
	chunk_end_time_ = 0;
	chunk_index_records_.clear();
}

Status McapWriter::open(const std::string &path, std::string_view profile, std::string_view library)
{
	if (is_open())
		return Error{ "cannot open " + path + ": the MCAP writer is still writing " + path_ };
	reset_state();
	path_ = path;
	if (!fits_u32(profile.size()) || !fits_u32(library.size()))
		return Error{ path + ": profile or library name too long" };

	if (options_.compression == McapCompression::zstd && !zstd_) {
		zstd_ = ZSTD_createCCtx();
		if (!zstd_)
			return Error{ path + ": cannot create a zstd compression context" };
	}
	if (zstd_) {
		// zstd would clamp a level out of its range without a word.
		const int level = options_.zstd_level;
		if (level < ZSTD_minCLevel() || level > ZSTD_maxCLevel())
			return Error{ path + ": zstd level " + std::to_string(level) + " is not in " +
				      std::to_string(ZSTD_minCLevel()) + ".." + std::to_string(ZSTD_maxCLevel()) };
		size_t r = ZSTD_CCtx_reset(zstd_, ZSTD_reset_session_only); // (a frame a failed file left open)
		if (!ZSTD_isError(r))
			r = ZSTD_CCtx_setParameter(zstd_, ZSTD_c_compressionLevel, level);
		if (ZSTD_isError(r))
			return Error{ path + ": zstd level " + std::to_string(level) + ": " + ZSTD_getErrorName(r) };
	}

	int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
	if (fd < 0)
		return errno_error(path);
	fd_.reset(fd);
	chunk_.reserve(options_.chunk_size + 4096);

	std::vector<uint8_t> head;
	put_bytes(head, kMcapMagic, sizeof kMcapMagic);
	size_t at = begin_record(head, mcap_header);
	put_string(head, profile);
	put_string(head, library);
	end_record(head, at);
	data_crc_ = mcap_crc32(data_crc_, head.data(), head.size());
	struct iovec iov = { head.data(), head.size() };
	Status s = write_all(&iov, 1);
	if (!s)
		fd_.reset();
	return s;
}

Result<uint16_t> McapWriter::add_schema(std::string_view name, std::string_view encoding, std::string_view data)
{
	if (Status s = failed_status(); !s)
		return s.error();
	if (!fits_u32(name.size()) || !fits_u32(encoding.size()) || !fits_u32(data.size()))
		return Error{ path_ + ": schema " + std::string(name.substr(0, 80)) + ": too large for MCAP" };
	for (size_t i = 0; i < schemas_.size(); i++) {
		const Schema &s = schemas_[i];
		if (s.name == name && s.encoding == encoding && s.data == data)
			return uint16_t(i + 1);
	}
	if (schemas_.size() >= UINT16_MAX)
		return Error{ path_ + ": schema " + std::string(name) + ": more than 65535 schemas" };
	schemas_.push_back(Schema{ std::string(name), std::string(encoding), std::string(data) });
	return uint16_t(schemas_.size());
}

Result<uint16_t> McapWriter::add_channel(std::string_view topic, std::string_view message_encoding,
					 uint16_t schema_id, const Metadata &metadata)
{
	if (Status s = failed_status(); !s)
		return s.error();
	std::string what = path_ + ": channel " + std::string(topic.substr(0, 200));
	if (schema_id > schemas_.size())
		return Error{ what + ": no schema " + std::to_string(schema_id) };
	if (channels_.size() > UINT16_MAX)
		return Error{ what + ": more than 65536 channels" };
	if (!fits_u32(topic.size()) || !fits_u32(message_encoding.size()) || metadata_bytes(metadata) > UINT32_MAX)
		return Error{ what + ": too large for MCAP" };
	Channel c;
	c.topic = topic;
	c.message_encoding = message_encoding;
	c.schema_id = schema_id;
	c.metadata = metadata;
	channels_.push_back(std::move(c));
	return uint16_t(channels_.size() - 1);
}

Status McapWriter::write(uint16_t channel_id, uint64_t log_time_ns, uint64_t publish_time_ns, const void *data,
			 size_t size)
{
	if (error_ || !is_open())
		return failed_status();
	if (channel_id >= channels_.size())
		return Error{ path_ + ": message on channel " + std::to_string(channel_id) + ", which was never added" };
	Channel &c = channels_[channel_id];

	// First message on this channel in this chunk: make the chunk
	// self-contained by giving it the channel (and its schema) first.
	if (c.in_chunk != chunk_gen_) {
		if (c.schema_id != 0) {
			Schema &s = schemas_[c.schema_id - 1];
			if (s.in_chunk != chunk_gen_) {
				put_schema(chunk_, c.schema_id, s);
				s.in_chunk = chunk_gen_;
			}
		}
		put_channel(chunk_, channel_id, c);
		c.in_chunk = chunk_gen_;
		chunk_channels_.push_back(channel_id);
	}

	// The head and the message in one step: a few stores and a copy (the
	// coordinator writes several messages a cycle).
	const uint64_t at = chunk_.size();
	chunk_.resize(at + kMessageHead + size);
	uint8_t *head = chunk_.data() + at;
	const uint64_t length = uint64_t(kMessageHead - 9) + size;
	const uint16_t channel = channel_id;
	const uint32_t sequence = c.sequence;
	head[0] = mcap_message;
	std::memcpy(head + 1, &length, 8);
	std::memcpy(head + 9, &channel, 2);
	std::memcpy(head + 11, &sequence, 4);
	std::memcpy(head + 15, &log_time_ns, 8);
	std::memcpy(head + 23, &publish_time_ns, 8);
	if (size)
		std::memcpy(head + kMessageHead, data, size);

	if (!c.index.empty() && log_time_ns < c.index.back().log_time)
		c.unsorted = true;
	c.index.push_back(IndexEntry{ log_time_ns, at });
	c.sequence++;
	c.message_count++;
	message_count_++;
	chunk_start_time_ = std::min(chunk_start_time_, log_time_ns);
	chunk_end_time_ = std::max(chunk_end_time_, log_time_ns);

	if (chunk_.size() >= options_.chunk_size)
		return finish_chunk();
	if (chunk_.size() - fed_ >= kFeedPiece)
		return feed(ZSTD_e_flush);
	return Ok{};
}

void McapWriter::restart_chunk()
{
	chunk_.clear();
	fed_ = 0;
	chunk_crc_ = 0;
	zpos_ = 0;
}

// What the chunk holds past fed_, into its CRC and (compressing) into
// compressed_: with ZSTD_e_flush, compressed now as a block of the chunk's
// frame; with ZSTD_e_end, the frame ended.
Status McapWriter::feed(int directive)
{
	const uint8_t *from = chunk_.data() + fed_;
	const size_t n = chunk_.size() - fed_;
	chunk_crc_ = mcap_crc32(chunk_crc_, from, n);
	fed_ = chunk_.size();
	if (!zstd_)
		return Ok{};
	ZSTD_inBuffer in = { from, n, 0 };
	for (;;) {
		if (compressed_.size() - zpos_ < ZSTD_compressBound(in.size - in.pos) + 64)
			compressed_.resize(std::max(2 * compressed_.size(), zpos_ + ZSTD_compressBound(in.size - in.pos) + 64));
		ZSTD_outBuffer out = { compressed_.data(), compressed_.size(), zpos_ };
		size_t left = ZSTD_compressStream2(zstd_, &out, &in, ZSTD_EndDirective(directive));
		zpos_ = out.pos;
		if (ZSTD_isError(left)) {
			error_ = Error{ path_ + ": zstd compression failed: " + ZSTD_getErrorName(left) };
			return *error_;
		}
		if (left == 0 && in.pos == in.size)
			return Ok{};
	}
}

Status McapWriter::flush()
{
	if (error_ || !is_open())
		return failed_status();
	return finish_chunk();
}

Status McapWriter::write_all(const struct iovec *iov_in, int count)
{
	std::array<struct iovec, 4> iov;
	if (count > int(iov.size()))
		return Error{ path_ + ": internal error: too many pieces to write" };
	uint64_t total = 0;
	for (int i = 0; i < count; i++) {
		iov[i] = iov_in[i];
		total += iov[i].iov_len;
	}
	struct iovec *v = iov.data();
	int n = count;
	while (n > 0) {
		if (v->iov_len == 0) {
			v++, n--;
			continue;
		}
		ssize_t w = ::writev(fd_.get(), v, std::min(n, IOV_MAX));
		if (w < 0) {
			if (errno == EINTR)
				continue;
			return set_error("write", errno);
		}
		// A short write (a full disk, a signal): continue where it stopped.
		size_t left = size_t(w);
		while (n > 0 && left >= v->iov_len) {
			left -= v->iov_len;
			v++, n--;
		}
		if (n > 0) {
			v->iov_base = static_cast<uint8_t *>(v->iov_base) + left;
			v->iov_len -= left;
		}
	}
	offset_ += total;
	return Ok{};
}

// Chunk record, then one Message Index record per channel in it, written
// with one writev; the matching Chunk Index record is kept for the summary.
Status McapWriter::finish_chunk()
{
	if (chunk_.empty())
		return Ok{};
	const uint64_t uncompressed_size = chunk_.size();
	if (Status s = feed(ZSTD_e_end); !s)
		return s;
	const uint32_t crc = chunk_crc_;

	const uint8_t *payload = chunk_.data();
	uint64_t payload_size = uncompressed_size;
	std::string_view compression;
	// Incompressible data is stored as it is (readers decide per chunk).
	if (zstd_ && zpos_ < chunk_.size()) {
		payload = compressed_.data();
		payload_size = zpos_;
		compression = "zstd";
	}

	chunk_head_.clear();
	size_t at = begin_record(chunk_head_, mcap_chunk);
	put_u64(chunk_head_, chunk_start_time_);
	put_u64(chunk_head_, chunk_end_time_);
	put_u64(chunk_head_, uncompressed_size);
	put_u32(chunk_head_, crc);
	put_string(chunk_head_, compression);
	put_u64(chunk_head_, payload_size);
	store_le(chunk_head_.data() + at, chunk_head_.size() - at - 8 + payload_size, 8);
	const uint64_t chunk_offset = offset_;
	const uint64_t chunk_length = chunk_head_.size() + payload_size;

	// Message Index records in channel order, and the Chunk Index record
	// that points at them.
	std::sort(chunk_channels_.begin(), chunk_channels_.end());
	message_indexes_.clear();
	std::vector<uint8_t> &ci = chunk_index_records_;
	size_t ci_at = begin_record(ci, mcap_chunk_index);
	put_u64(ci, chunk_start_time_);
	put_u64(ci, chunk_end_time_);
	put_u64(ci, chunk_offset);
	put_u64(ci, chunk_length);
	put_u32(ci, uint32_t(chunk_channels_.size() * (2 + 8)));
	for (uint16_t id : chunk_channels_) {
		Channel &c = channels_[id];
		if (c.unsorted)
			std::sort(c.index.begin(), c.index.end(), [](const IndexEntry &a, const IndexEntry &b) {
				return a.log_time != b.log_time ? a.log_time < b.log_time : a.offset < b.offset;
			});
		put_u16(ci, id);
		put_u64(ci, chunk_offset + chunk_length + message_indexes_.size());
		size_t mi_at = begin_record(message_indexes_, mcap_message_index);
		put_u16(message_indexes_, id);
		put_u32(message_indexes_, uint32_t(c.index.size() * 16));
		// The entries as they are held: (log time, offset), each a
		// little-endian u64, as MCAP lays them out.
		put_bytes(message_indexes_, c.index.data(), c.index.size() * sizeof(IndexEntry));
		end_record(message_indexes_, mi_at);
	}
	put_u64(ci, message_indexes_.size());
	put_string(ci, compression);
	put_u64(ci, payload_size);
	put_u64(ci, uncompressed_size);
	end_record(ci, ci_at);

	struct iovec iov[3] = {
		{ chunk_head_.data(), chunk_head_.size() },
		{ const_cast<uint8_t *>(payload), size_t(payload_size) },
		{ message_indexes_.data(), message_indexes_.size() },
	};
	// The data section's CRC: an uncompressed payload's is the chunk's,
	// already computed as it filled, not read again.
	data_crc_ = mcap_crc32(data_crc_, chunk_head_.data(), chunk_head_.size());
	if (payload == chunk_.data())
		data_crc_ = mcap_crc32_combine(data_crc_, crc, payload_size);
	else
		data_crc_ = mcap_crc32(data_crc_, payload, payload_size);
	data_crc_ = mcap_crc32(data_crc_, message_indexes_.data(), message_indexes_.size());
	if (Status s = write_all(iov, 3); !s)
		return s;

	chunk_count_++;
	start_time_ = std::min(start_time_, chunk_start_time_);
	end_time_ = std::max(end_time_, chunk_end_time_);
	for (uint16_t id : chunk_channels_) {
		channels_[id].index.clear();
		channels_[id].unsorted = false;
	}
	chunk_channels_.clear();
	restart_chunk();
	chunk_gen_++;
	chunk_start_time_ = UINT64_MAX;
	chunk_end_time_ = 0;
	return Ok{};
}

// Data End, then the summary grouped by opcode (Schemas, Channels,
// Statistics, Chunk Indexes), a Summary Offset per group, the Footer and
// the magic, in one write.
Status McapWriter::close()
{
	if (!is_open())
		return error_ ? Status(*error_) : Status(Ok{});
	if (error_) {
		fd_.reset();
		return *error_;
	}
	if (Status s = finish_chunk(); !s) {
		fd_.reset();
		return s;
	}

	std::vector<uint8_t> tail;
	size_t at = begin_record(tail, mcap_data_end);
	put_u32(tail, data_crc_);
	end_record(tail, at);
	const size_t summary_at = tail.size();
	const uint64_t summary_start = offset_ + summary_at;

	struct Group {
		McapOpcode op;
		size_t begin, end;
	};
	std::vector<Group> groups;
	auto group = [&](McapOpcode op, auto &&emit) {
		size_t begin = tail.size();
		emit();
		if (tail.size() > begin)
			groups.push_back(Group{ op, begin, tail.size() });
	};
	group(mcap_schema, [&] {
		for (size_t i = 0; i < schemas_.size(); i++)
			put_schema(tail, uint16_t(i + 1), schemas_[i]);
	});
	group(mcap_channel, [&] {
		for (size_t i = 0; i < channels_.size(); i++)
			put_channel(tail, uint16_t(i), channels_[i]);
	});
	group(mcap_statistics, [&] {
		size_t s = begin_record(tail, mcap_statistics);
		put_u64(tail, message_count_);
		put_u16(tail, uint16_t(schemas_.size()));
		put_u32(tail, uint32_t(channels_.size()));
		put_u32(tail, 0); // attachments
		put_u32(tail, 0); // metadata
		put_u32(tail, chunk_count_);
		put_u64(tail, message_count_ ? start_time_ : 0);
		put_u64(tail, message_count_ ? end_time_ : 0);
		put_u32(tail, uint32_t(channels_.size() * (2 + 8)));
		for (size_t i = 0; i < channels_.size(); i++) {
			put_u16(tail, uint16_t(i));
			put_u64(tail, channels_[i].message_count);
		}
		end_record(tail, s);
	});
	group(mcap_chunk_index, [&] { put_bytes(tail, chunk_index_records_.data(), chunk_index_records_.size()); });

	const uint64_t summary_offset_start = offset_ + tail.size();
	for (const Group &g : groups) {
		size_t s = begin_record(tail, mcap_summary_offset);
		put_u8(tail, g.op);
		put_u64(tail, offset_ + g.begin);
		put_u64(tail, g.end - g.begin);
		end_record(tail, s);
	}

	// The summary CRC runs from the summary's first byte through the
	// Footer's summary_offset_start field, so the Footer's length must be
	// in place before it is computed.
	put_u8(tail, mcap_footer);
	put_u64(tail, 8 + 8 + 4);
	put_u64(tail, summary_start);
	put_u64(tail, summary_offset_start);
	put_u32(tail, mcap_crc32(0, tail.data() + summary_at, tail.size() - summary_at));
	put_bytes(tail, kMcapMagic, sizeof kMcapMagic);

	struct iovec iov = { tail.data(), tail.size() };
	Status s = write_all(&iov, 1);
	if (!s) {
		fd_.reset();
		return s;
	}
	if (::close(fd_.release()) != 0)
		return set_error("close", errno);
	return Ok{};
}

} // namespace tcs
