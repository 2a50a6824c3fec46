// The MCAP reader: walks the records from the leading magic, opens each
// chunk (zstd or uncompressed, CRC-checked) and hands out its messages.
#include "mcap_reader.h"
#include "mcap_format.h"
#include "read_file.h"

#include <cstring>

namespace tcs {

namespace {

// A trace is read whole into memory: refuse what could not be one before
// memory runs out (a 100 s run at 1 kHz makes about 26 MB).
constexpr size_t kMaxFileBytes = size_t(16) << 30;

} // namespace

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
	McapRecord r;
	if (!whole_record(&r))
		return Ok{};
	if (r.op != mcap_header)
		return error_at(pos_, "the first record has opcode " + std::to_string(r.op) + ", not a Header's");
	McapHeader h;
	if (std::string what = mcap_decode_header(r.body, &h); !what.empty())
		return error_at(pos_, what);
	profile_ = h.profile;
	library_ = h.library;
	pos_ += kMcapRecordHead + r.body.size();
	return Ok{};
}

Error McapReader::error_at(uint64_t at, const std::string &what)
{
	error_ = Error{ name_ + ": at byte " + std::to_string(at) + ": " + what };
	return *error_;
}

bool McapReader::whole_record(McapRecord *record)
{
	if (!mcap_record_at(bytes_, pos_, record)) {
		truncated_ = true;
		bytes_unread_ = bytes_.size() - pos_;
		done_ = true;
		return false;
	}
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
		McapRecord record;
		if (!whole_record(&record))
			return false;
		pos_ += kMcapRecordHead + record.body.size();
		if (record.op == mcap_footer) {
			Status s = footer();
			if (!s)
				return s.error();
			return false;
		}
		if (in_summary_)
			continue; // what the summary holds, the data section had
		Result<bool> r = top_level(record, out);
		if (!r || *r)
			return r;
	}
}

// One record of the data section (outside chunks): true when it is a
// message, now in *out.
Result<bool> McapReader::top_level(const McapRecord &record, McapMessage *out)
{
	switch (record.op) {
	case mcap_header:
		return error_at(record.offset, "a second Header");
	case mcap_schema:
	case mcap_channel: {
		std::string what = definition(record);
		if (!what.empty())
			return error_at(record.offset, what);
		return false;
	}
	case mcap_message: {
		std::string what = message(record.body, out);
		if (!what.empty())
			return error_at(record.offset, what);
		return true;
	}
	case mcap_chunk: {
		Status s = open_chunk(record);
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
Status McapReader::open_chunk(const McapRecord &record)
{
	McapChunk chunk;
	std::string_view records;
	std::string what = mcap_decode_chunk(record.body, &chunk);
	if (what.empty())
		what = unpacker_.unpack(chunk, &records);
	if (!what.empty())
		return error_at(record.offset, what);
	records_in_buf_ = !chunk.compression.empty();
	records_off_ = records_in_buf_ ? 0 : size_t(records.data() - bytes_.data());
	records_len_ = records.size();
	records_pos_ = 0;
	chunk_at_ = record.offset;
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
	McapRecord record;
	if (!mcap_record_at(recs, at, &record)) {
		if (left < kMcapRecordHead)
			return bad("a record cut short by the end of the Chunk");
		uint64_t len = 0;
		for (size_t i = 0; i < 8; i++)
			len |= uint64_t(uint8_t(recs[at + 1 + i])) << (8 * i);
		return bad("a record of " + std::to_string(len) + " bytes runs past the end of the Chunk");
	}
	records_pos_ += kMcapRecordHead + record.body.size();

	switch (record.op) {
	case mcap_schema:
	case mcap_channel: {
		std::string what = definition(record);
		if (!what.empty())
			return bad(what);
		return false;
	}
	case mcap_message: {
		std::string what = message(record.body, out);
		if (!what.empty())
			return bad(what);
		return true;
	}
	case mcap_header:
	case mcap_footer:
	case mcap_chunk:
	case mcap_data_end:
		return bad("a record with opcode " + std::to_string(record.op) + ", which a Chunk cannot hold");
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
std::string McapReader::definition(const McapRecord &record)
{
	size_t known = 0;
	if (record.op == mcap_schema) {
		McapSchema s;
		if (std::string what = mcap_decode_schema(record.body, &s, &known); !what.empty())
			return what;
		const uint16_t id = s.id;
		return define(schema_records_, schemas_, id, record.body.substr(0, known), std::move(s), "Schema");
	}
	McapChannel c;
	if (std::string what = mcap_decode_channel(record.body, &c, &known); !what.empty())
		return what;
	if (c.schema_id != 0 && !schemas_.count(c.schema_id))
		return "Channel " + std::to_string(c.id) + " refers to Schema " + std::to_string(c.schema_id) +
		       ", which no Schema record defined before it";
	const uint16_t id = c.id;
	return define(channel_records_, channels_, id, record.body.substr(0, known), std::move(c), "Channel");
}

// A Message record into *out: "" or what is wrong with it.
std::string McapReader::message(std::string_view body, McapMessage *out)
{
	McapMessageFields f;
	if (std::string what = mcap_decode_message(body, &f); !what.empty())
		return what;
	auto it = channels_.find(f.channel_id);
	if (it == channels_.end())
		return "a Message on channel " + std::to_string(f.channel_id) +
		       ", which no Channel record defined before it";
	out->channel = &it->second;
	out->schema = nullptr;
	if (it->second.schema_id != 0)
		out->schema = &schemas_.at(it->second.schema_id);
	out->sequence = f.sequence;
	out->log_time = f.log_time;
	out->publish_time = f.publish_time;
	out->data = f.data;
	return "";
}

Status for_each_message(McapReader &reader, const std::function<Status(const McapMessage &)> &f, bool *truncated)
{
	McapMessage m;
	for (;;) {
		auto more = reader.next(&m);
		if (!more)
			return more.error();
		if (!*more)
			break;
		if (auto s = f(m); !s)
			return s;
	}
	if (truncated)
		*truncated = reader.truncated();
	return Ok{};
}

Status for_each_message(const std::string &path, const std::function<Status(const McapMessage &)> &f, bool *truncated)
{
	McapReader reader;
	if (auto s = reader.open(path); !s)
		return s;
	return for_each_message(reader, f, truncated);
}

} // namespace tcs
