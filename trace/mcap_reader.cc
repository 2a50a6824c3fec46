// The MCAP reader: walks the records from the leading magic, opens each
// chunk (zstd or uncompressed, CRC-checked) and hands out its messages.
#include "mcap_reader.h"
#include "mcap_format.h"
#include "read_file.h"

#include <zstd.h>

#include <cstdio>
#include <cstring>

#include "mcap_writer.h"

namespace tcs {

namespace {

// A trace is read whole into memory: refuse what could not be one before
// memory runs out (a 100 s run at 1 kHz makes about 26 MB).
constexpr size_t kMaxFileBytes = size_t(16) << 30;

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

uint64_t le64(const char *p)
{
	uint64_t v = 0;
	for (int i = 0; i < 8; i++)
		v |= uint64_t(uint8_t(p[i])) << (8 * i);
	return v;
}

// A string from the file, fit to quote in a message.
std::string printable(std::string_view s)
{
	std::string out;
	for (char c : s.substr(0, 40))
		out += c >= 0x20 && c < 0x7F ? c : '?';
	return s.size() > 40 ? out + "..." : out;
}

std::string hex32(uint32_t v)
{
	char buf[16];
	snprintf(buf, sizeof buf, "0x%08x", v);
	return buf;
}

} // namespace

McapReader::Zstd::~Zstd() { ZSTD_freeDCtx(dctx); }

Status McapReader::open(const std::string &path)
{
	auto bytes = read_file(path, kMaxFileBytes);
	if (!bytes)
		return bytes.error();
	return open_bytes(path, std::move(*bytes));
}

Status McapReader::open_bytes(std::string name, std::string bytes)
{
	name_ = std::move(name);
	bytes_ = std::move(bytes);
	profile_.clear();
	library_.clear();
	channels_.clear();
	schemas_.clear();
	schema_records_.clear();
	channel_records_.clear();
	truncated_ = false;
	bytes_unread_ = 0;
	error_.reset();
	done_ = false;
	in_summary_ = false;
	records_len_ = 0;
	records_pos_ = 0;
	chunk_at_ = 0;

	if (bytes_.size() < sizeof kMcapMagic || std::memcmp(bytes_.data(), kMcapMagic, sizeof kMcapMagic) != 0)
		return Error{ name_ + ": not an MCAP file" };
	pos_ = sizeof kMcapMagic;
	// The Header, if all of it is there; a file cut inside it is a run
	// killed at once, which next() reports as truncated.
	std::string_view body;
	uint8_t op;
	if (!whole_record(&op, &body))
		return Ok{};
	if (op != mcap_header)
		return error_at(pos_, "the first record has opcode " + std::to_string(op) + ", not a Header's");
	Fields f(body);
	std::string_view profile = f.str(), library = f.str();
	if (!f.ok())
		return error_at(pos_, "the Header's strings run past its " + std::to_string(body.size()) + " bytes");
	profile_ = profile;
	library_ = library;
	pos_ += kMcapRecordHead + body.size();
	return Ok{};
}

Error McapReader::error_at(uint64_t at, const std::string &what)
{
	error_ = Error{ name_ + ": at byte " + std::to_string(at) + ": " + what };
	return *error_;
}

bool McapReader::whole_record(uint8_t *op, std::string_view *body)
{
	const size_t left = bytes_.size() - pos_;
	if (left < kMcapRecordHead || le64(bytes_.data() + pos_ + 1) > left - kMcapRecordHead) {
		truncated_ = true;
		bytes_unread_ = left;
		done_ = true;
		return false;
	}
	*op = uint8_t(bytes_[pos_]);
	*body = std::string_view(bytes_).substr(pos_ + kMcapRecordHead, size_t(le64(bytes_.data() + pos_ + 1)));
	return true;
}

Result<bool> McapReader::next(McapMessage *out)
{
	if (error_)
		return *error_;
	for (;;) {
		if (records_pos_ < records_len_) {
			Result<bool> r = next_in_chunk(out);
			if (!r || *r)
				return r;
			continue;
		}
		if (done_)
			return false;
		std::string_view body;
		uint8_t op;
		if (!whole_record(&op, &body))
			return false;
		const uint64_t at = pos_;
		pos_ += kMcapRecordHead + body.size();
		if (op == mcap_footer) {
			Status s = footer();
			if (!s)
				return s.error();
			return false;
		}
		if (in_summary_)
			continue; // what the summary holds, the data section had
		Result<bool> r = top_level(at, op, body, out);
		if (!r || *r)
			return r;
	}
}

// One record of the data section (outside chunks): true when it is a
// message, now in *out.
Result<bool> McapReader::top_level(uint64_t at, uint8_t op, std::string_view body, McapMessage *out)
{
	switch (op) {
	case mcap_header:
		return error_at(at, "a second Header");
	case mcap_schema:
	case mcap_channel: {
		std::string what = definition(op, body);
		if (!what.empty())
			return error_at(at, what);
		return false;
	}
	case mcap_message: {
		std::string what = message(body, out);
		if (!what.empty())
			return error_at(at, what);
		return true;
	}
	case mcap_chunk: {
		Status s = open_chunk(at, body);
		if (!s)
			return s.error();
		return false;
	}
	case mcap_data_end:
		// The summary follows: it repeats what the data section held,
		// so it is only walked through to the Footer.
		in_summary_ = true;
		return false;
	default:
		// Indexes, attachments, metadata, and opcodes of later
		// versions of the format: skipped, as the spec requires.
		return false;
	}
}

Status McapReader::footer()
{
	done_ = true;
	const size_t left = bytes_.size() - pos_;
	if (left < sizeof kMcapMagic) {
		if (std::memcmp(bytes_.data() + pos_, kMcapMagic, left) != 0)
			return error_at(pos_, "the Footer is not followed by the closing magic");
		truncated_ = true;
		bytes_unread_ = left;
		return Ok{};
	}
	if (std::memcmp(bytes_.data() + pos_, kMcapMagic, sizeof kMcapMagic) != 0)
		return error_at(pos_, "the Footer is not followed by the closing magic");
	if (left > sizeof kMcapMagic)
		return error_at(pos_ + sizeof kMcapMagic, std::to_string(left - sizeof kMcapMagic) + " bytes after the closing magic");
	return Ok{};
}

// Checks a Chunk record and makes its records the ones next() reads.
Status McapReader::open_chunk(uint64_t at, std::string_view body)
{
	Fields f(body);
	f.u64(); // message start and end times: the messages have their own
	f.u64();
	const uint64_t size = f.u64();
	const uint32_t crc = f.u32();
	const std::string_view compression = f.str();
	const uint64_t stored_size = f.u64();
	const std::string_view stored = f.bytes(stored_size);
	if (!f.ok())
		return error_at(at, "the Chunk's fields run past its " + std::to_string(body.size()) + " bytes");
	if (size > kMaxChunkBytes)
		return error_at(at, "the Chunk declares " + std::to_string(size) +
					" uncompressed bytes, more than the 1 GiB this reader accepts");

	std::string_view records;
	bool in_buf = false;
	if (compression.empty()) {
		if (stored.size() != size)
			return error_at(at, "the uncompressed Chunk holds " + std::to_string(stored.size()) +
						" bytes of records but declares " + std::to_string(size));
		records = stored;
	} else if (compression == "zstd") {
		if (size > stored.size() * kMaxZstdRatio)
			return error_at(at, "the Chunk declares " + std::to_string(size) + " uncompressed bytes, more than " +
						std::to_string(stored.size()) + " bytes of zstd data can hold");
		if (size > 0 || !stored.empty()) {
			// The frame states its size too: a mismatch is damage,
			// found before allocating anything.
			unsigned long long frame = ZSTD_getFrameContentSize(stored.data(), stored.size());
			if (frame == ZSTD_CONTENTSIZE_ERROR)
				return error_at(at, "the Chunk's records are not a zstd frame");
			if (frame != ZSTD_CONTENTSIZE_UNKNOWN && frame != size)
				return error_at(at, "the Chunk's zstd frame holds " + std::to_string(frame) +
							" bytes but the Chunk declares " + std::to_string(size));
			if (chunk_buf_.size() < size)
				chunk_buf_.resize(size_t(size));
			if (!zstd_.dctx && !(zstd_.dctx = ZSTD_createDCtx()))
				return error_at(at, "cannot create a zstd decompression context");
			size_t n = ZSTD_decompressDCtx(zstd_.dctx, chunk_buf_.data(), size_t(size), stored.data(),
						       stored.size());
			if (ZSTD_isError(n))
				return error_at(at, std::string("the Chunk's zstd data is damaged: ") + ZSTD_getErrorName(n));
			if (n != size)
				return error_at(at, "the Chunk's zstd data decompresses to " + std::to_string(n) +
							" bytes but the Chunk declares " + std::to_string(size));
		}
		records = std::string_view(chunk_buf_).substr(0, size_t(size));
		in_buf = true;
	} else if (compression == "lz4") {
		return error_at(at, "the Chunk is lz4-compressed: lz4 chunks are not supported (only zstd and none)");
	} else {
		return error_at(at, "the Chunk's compression '" + printable(compression) + "' is unknown");
	}
	// A CRC of 0 means the writer did not compute one.
	if (crc != 0) {
		uint32_t got = mcap_crc32(0, records.data(), records.size());
		if (got != crc)
			return error_at(at, "the CRC of the Chunk's records is " + hex32(got) + ", the Chunk says " +
						hex32(crc));
	}
	records_in_buf_ = in_buf;
	records_off_ = in_buf ? 0 : size_t(records.data() - bytes_.data());
	records_len_ = records.size();
	records_pos_ = 0;
	chunk_at_ = at;
	return Ok{};
}

// The next record of the open chunk: true when it is a message, now in
// *out. The chunk is whole, so a record running past its end is damage.
Result<bool> McapReader::next_in_chunk(McapMessage *out)
{
	const std::string_view recs = records();
	const size_t at = records_pos_, left = recs.size() - at;
	auto bad = [&](const std::string &what) {
		records_len_ = 0;
		records_pos_ = 0;
		return error_at(chunk_at_, "in the Chunk's records at offset " + std::to_string(at) + ": " + what);
	};
	if (left < kMcapRecordHead)
		return bad("a record cut short by the end of the Chunk");
	const uint8_t op = uint8_t(recs[at]);
	const uint64_t len = le64(recs.data() + at + 1);
	if (len > left - kMcapRecordHead)
		return bad("a record of " + std::to_string(len) + " bytes runs past the end of the Chunk");
	const std::string_view body = recs.substr(at + kMcapRecordHead, size_t(len));
	records_pos_ += kMcapRecordHead + size_t(len);

	switch (op) {
	case mcap_schema:
	case mcap_channel: {
		std::string what = definition(op, body);
		if (!what.empty())
			return bad(what);
		return false;
	}
	case mcap_message: {
		std::string what = message(body, out);
		if (!what.empty())
			return bad(what);
		return true;
	}
	case mcap_header:
	case mcap_footer:
	case mcap_chunk:
	case mcap_data_end:
		return bad("a record with opcode " + std::to_string(op) + ", which a Chunk cannot hold");
	default:
		return false; // unknown to this version: skipped
	}
}

// A definition's first appearance is kept; one again must be the same bytes
// (known: the fields this version reads, since a later one may append
// fields, which are not compared). "" or what is wrong.
template <class T>
static std::string define(std::map<uint16_t, std::string> &records, std::map<uint16_t, T> &defined, uint16_t id,
			  std::string_view known, T value, const char *what)
{
	auto [it, fresh] = records.emplace(id, known);
	if (!fresh && it->second != known)
		return what + (" " + std::to_string(id)) + " redefined differently";
	if (fresh)
		defined[id] = std::move(value);
	return "";
}

// A Schema or Channel record: "" when it is fine (a new definition, or the
// same one again), or what is wrong with it.
std::string McapReader::definition(uint8_t op, std::string_view body)
{
	Fields f(body);
	const uint16_t id = f.u16();
	if (op == mcap_schema) {
		McapSchema s;
		s.id = id;
		s.name = f.str();
		s.encoding = f.str();
		s.data = f.str();
		if (!f.ok())
			return "the Schema's fields run past its " + std::to_string(body.size()) + " bytes";
		if (id == 0)
			return "a Schema with id 0, which means \"no schema\"";
		return define(schema_records_, schemas_, id, body.substr(0, f.used()), std::move(s), "Schema");
	}
	McapChannel c;
	c.id = id;
	c.schema_id = f.u16();
	c.topic = f.str();
	c.message_encoding = f.str();
	Fields metadata(f.bytes(f.u32()));
	if (!f.ok())
		return "the Channel's fields run past its " + std::to_string(body.size()) + " bytes";
	while (metadata.ok() && metadata.left() > 0) {
		metadata.str();
		metadata.str();
	}
	if (!metadata.ok())
		return "the metadata of Channel " + std::to_string(id) + " is malformed";
	if (c.schema_id != 0 && !schemas_.count(c.schema_id))
		return "Channel " + std::to_string(id) + " refers to Schema " + std::to_string(c.schema_id) +
		       ", which no Schema record defined before it";
	return define(channel_records_, channels_, id, body.substr(0, f.used()), std::move(c), "Channel");
}

// A Message record into *out: "" or what is wrong with it.
std::string McapReader::message(std::string_view body, McapMessage *out)
{
	Fields f(body);
	const uint16_t channel = f.u16();
	const uint32_t sequence = f.u32();
	const uint64_t log_time = f.u64(), publish_time = f.u64();
	if (!f.ok())
		return "a Message of " + std::to_string(body.size()) + " bytes, shorter than its fixed fields";
	auto it = channels_.find(channel);
	if (it == channels_.end())
		return "a Message on channel " + std::to_string(channel) + ", which no Channel record defined before it";
	out->channel = &it->second;
	out->schema = nullptr;
	if (it->second.schema_id != 0)
		out->schema = &schemas_.at(it->second.schema_id);
	out->sequence = sequence;
	out->log_time = log_time;
	out->publish_time = publish_time;
	out->data = body.substr(f.used());
	return "";
}

} // namespace tcs
