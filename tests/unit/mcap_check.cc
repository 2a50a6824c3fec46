// Reads an MCAP file back for the writer's tests (see mcap_check.h): the
// messages with McapReader, the layout with mcap_records.h's decoders,
// each checked against the other. What the reader checks itself (a Message
// before its Channel, a definition repeated differently, a chunk's CRC
// when not 0) is its errors'; this adds what a reader may pass over but a
// writer must get right.
#include "mcap_check.h"

#include <algorithm>
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <set>
#include <utility>

extern "C" {
#include <cmocka.h>
}

#include "mcap_format.h"
#include "mcap_reader.h"

namespace mcap_check {

namespace {

using tcs::McapRecord;

// Walks the records of a file that McapReader has read without an error.
class Layout {
public:
	Layout(const std::string &f, ReadBack &out) : f_(f), out_(out) {}

	void check()
	{
		if (data_section() && out_.complete)
			cross_check();
	}

private:
	// The chunk whose Message Index records may follow: each channel's
	// (log time, offset) pairs, and the channels indexed so far.
	struct Open {
		std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> entries;
		std::set<uint16_t> indexed;
	};

	bool problem(const char *fmt, ...) __attribute__((format(printf, 2, 3)))
	{
		if (out_.error.empty()) {
			char buf[512];
			va_list ap;
			va_start(ap, fmt);
			vsnprintf(buf, sizeof buf, fmt, ap);
			va_end(ap);
			out_.error = buf;
		}
		return false;
	}

	// A decoder's verdict on a record this writer made: its fields, and
	// nothing after them (*known is read once the decoder has set it).
	bool decoded(const std::string &what, const size_t *known, const McapRecord &r, const char *kind)
	{
		if (!what.empty())
			return problem("%s at %lu: %s", kind, (unsigned long)r.offset, what.c_str());
		if (*known != r.body.size())
			return problem("%s at %lu: %zu bytes after its fields", kind, (unsigned long)r.offset,
				       r.body.size() - *known);
		return true;
	}

	bool data_section()
	{
		McapRecord r;
		uint64_t pos = sizeof tcs::kMcapMagic;
		if (!tcs::mcap_record_at(f_, pos, &r))
			return true; // cut inside the Header
		tcs::McapHeader h;
		size_t known = 0;
		if (!decoded(tcs::mcap_decode_header(r.body, &h, &known), &known, r, "Header"))
			return false;
		pos += tcs::kMcapRecordHead + r.body.size();
		while (tcs::mcap_record_at(f_, pos, &r)) {
			pos += tcs::kMcapRecordHead + r.body.size();
			if (r.op == tcs::mcap_chunk) {
				if (!close_chunk() || !chunk(r))
					return false;
			} else if (r.op == tcs::mcap_message_index) {
				if (!message_index(r))
					return false;
			} else if (r.op == tcs::mcap_data_end) {
				uint32_t crc = 0;
				if (!close_chunk() || !decoded(tcs::mcap_decode_data_end(r.body, &crc, &known), &known, r, "Data End"))
					return false;
				if (crc != ref_crc32(f_.data(), r.offset))
					return problem("data section CRC 0x%08x is wrong", crc);
				return summary(pos);
			} else {
				return problem("opcode 0x%02x at %lu: not expected in this writer's data section", r.op,
					       (unsigned long)r.offset);
			}
		}
		// Cut short: the last chunk's Message Index records may be missing.
		return true;
	}

	bool chunk(const McapRecord &r)
	{
		tcs::McapChunk c;
		size_t known = 0;
		if (!decoded(tcs::mcap_decode_chunk(r.body, &c, &known), &known, r, "Chunk"))
			return false;
		std::string_view raw;
		if (std::string what = unpacker_.unpack(c, &raw); !what.empty())
			return problem("chunk at %lu: %s", (unsigned long)r.offset, what.c_str());
		// The reader takes a CRC of 0 for none; this writer computes every one.
		if (c.uncompressed_crc != ref_crc32(raw.data(), raw.size()))
			return problem("chunk at %lu: CRC 0x%08x of the uncompressed records is wrong", (unsigned long)r.offset,
				       c.uncompressed_crc);
		ChunkInfo info{ r.offset, tcs::kMcapRecordHead + r.body.size(), c.message_start_time, c.message_end_time,
				c.uncompressed_size, c.records.size(), std::string(c.compression), {}, 0, 0 };

		open_ = Open{};
		uint64_t lo = UINT64_MAX, hi = 0;
		McapRecord in;
		for (uint64_t at = 0; at < raw.size(); at += tcs::kMcapRecordHead + in.body.size()) {
			if (!tcs::mcap_record_at(raw, at, &in))
				return problem("chunk at %lu: record at %lu overruns the chunk", (unsigned long)r.offset,
					       (unsigned long)at);
			if (in.op == tcs::mcap_schema) {
				tcs::McapSchema s;
				if (!decoded(tcs::mcap_decode_schema(in.body, &s, &known), &known, in, "Schema in a chunk"))
					return false;
			} else if (in.op == tcs::mcap_channel) {
				tcs::McapChannel ch;
				if (!decoded(tcs::mcap_decode_channel(in.body, &ch, &known), &known, in, "Channel in a chunk"))
					return false;
			} else if (in.op == tcs::mcap_message) {
				tcs::McapMessageFields m;
				if (std::string what = tcs::mcap_decode_message(in.body, &m); !what.empty())
					return problem("chunk at %lu: %s", (unsigned long)r.offset, what.c_str());
				open_.entries[m.channel_id].push_back({ m.log_time, at });
				lo = std::min(lo, m.log_time);
				hi = std::max(hi, m.log_time);
				// The reader's messages, in the same order.
				const size_t i = seen_++;
				if (i >= out_.messages.size() || out_.messages[i].channel != m.channel_id ||
				    out_.messages[i].log != m.log_time)
					return problem("chunk at %lu: message %zu is not the reader's", (unsigned long)r.offset, i);
				info.messages++;
			} else {
				return problem("chunk at %lu: opcode 0x%02x inside a chunk", (unsigned long)r.offset, in.op);
			}
		}
		if (open_.entries.empty())
			lo = 0;
		if (c.message_start_time != lo || c.message_end_time != hi)
			return problem("chunk at %lu: times [%lu, %lu], messages [%lu, %lu]", (unsigned long)r.offset,
				       (unsigned long)c.message_start_time, (unsigned long)c.message_end_time,
				       (unsigned long)lo, (unsigned long)hi);
		out_.chunks.push_back(info);
		out_.messages_after_chunk.push_back(seen_);
		in_chunk_ = true;
		return true;
	}

	bool message_index(const McapRecord &r)
	{
		if (!in_chunk_)
			return problem("Message Index at %lu follows no chunk", (unsigned long)r.offset);
		tcs::McapMessageIndex mi;
		size_t known = 0;
		if (!decoded(tcs::mcap_decode_message_index(r.body, &mi, &known), &known, r, "Message Index"))
			return false;
		auto got = mi.records;
		for (size_t i = 1; i < got.size(); i++)
			if (got[i].first < got[i - 1].first)
				return problem("Message Index at %lu not in log time order", (unsigned long)r.offset);
		auto it = open_.entries.find(mi.channel_id);
		if (it == open_.entries.end() || !open_.indexed.insert(mi.channel_id).second)
			return problem("Message Index at %lu: channel %u has no messages here, or a second index",
				       (unsigned long)r.offset, mi.channel_id);
		auto want = it->second;
		std::sort(want.begin(), want.end());
		std::sort(got.begin(), got.end());
		if (got != want)
			return problem("Message Index at %lu does not point at channel %u's messages", (unsigned long)r.offset,
				       mi.channel_id);
		ChunkInfo &c = out_.chunks.back();
		c.mi_offsets[mi.channel_id] = r.offset;
		c.mi_length += tcs::kMcapRecordHead + r.body.size();
		return true;
	}

	bool close_chunk()
	{
		if (in_chunk_ && open_.indexed.size() != open_.entries.size())
			return problem("chunk at %lu: %zu of %zu channels indexed", (unsigned long)out_.chunks.back().offset,
				       open_.indexed.size(), open_.entries.size());
		in_chunk_ = false;
		return true;
	}

	bool summary(uint64_t summary_start)
	{
		const size_t footer_len = tcs::kMcapRecordHead + 20, magic = sizeof tcs::kMcapMagic, n = f_.size();
		if (n < summary_start + footer_len + magic ||
		    std::memcmp(f_.data() + n - magic, tcs::kMcapMagic, magic) != 0)
			return true; // cut after Data End
		const size_t footer_at = n - magic - footer_len;
		McapRecord r;
		tcs::McapFooter ft;
		size_t known = 0;
		if (!tcs::mcap_record_at(f_, footer_at, &r) || r.op != tcs::mcap_footer || r.body.size() != 20)
			return problem("no Footer before the closing magic");
		if (!decoded(tcs::mcap_decode_footer(r.body, &ft, &known), &known, r, "Footer"))
			return false;
		if (ft.summary_start != summary_start)
			return problem("footer's summary_start %lu, but Data End ends at %lu", (unsigned long)ft.summary_start,
				       (unsigned long)summary_start);
		const uint64_t so_start = ft.summary_offset_start;
		if (so_start <= summary_start || so_start > footer_at)
			return problem("footer's summary_offset_start %lu is outside the summary", (unsigned long)so_start);
		// From the summary's start through the Footer's summary_offset_start.
		if (ft.summary_crc != ref_crc32(f_.data() + summary_start, footer_at + tcs::kMcapRecordHead + 16 - summary_start))
			return problem("summary CRC 0x%08x is wrong", ft.summary_crc);

		// Groups of one opcode each, in the summary; then their offsets.
		std::map<uint8_t, std::pair<uint64_t, uint64_t>> groups; // opcode -> start, length
		const std::string_view summary(f_.data(), so_start);
		uint8_t last = 0;
		for (uint64_t pos = summary_start; pos < so_start; pos += tcs::kMcapRecordHead + r.body.size()) {
			if (!tcs::mcap_record_at(summary, pos, &r))
				return problem("summary record at %lu overruns the summary", (unsigned long)pos);
			if (r.op != last && groups.count(r.op))
				return problem("summary opcode 0x%02x in two groups", r.op);
			last = r.op;
			auto &g = groups[r.op];
			if (g.second == 0)
				g.first = r.offset;
			g.second += tcs::kMcapRecordHead + r.body.size();
			if (!summary_record(r))
				return false;
		}
		std::map<uint8_t, std::pair<uint64_t, uint64_t>> offsets;
		const std::string_view offset_records(f_.data(), footer_at);
		for (uint64_t pos = so_start; pos < footer_at; pos += tcs::kMcapRecordHead + r.body.size()) {
			tcs::McapSummaryOffset so;
			if (!tcs::mcap_record_at(offset_records, pos, &r) || r.op != tcs::mcap_summary_offset)
				return problem("bad Summary Offset record at %lu", (unsigned long)pos);
			if (!decoded(tcs::mcap_decode_summary_offset(r.body, &so, &known), &known, r, "Summary Offset"))
				return false;
			offsets[so.group_opcode] = { so.group_start, so.group_length };
		}
		if (offsets != groups)
			return problem("Summary Offset records do not match the summary's groups");
		out_.complete = true;
		return true;
	}

	bool summary_record(const McapRecord &r)
	{
		size_t known = 0;
		switch (r.op) {
		case tcs::mcap_schema: {
			tcs::McapSchema s;
			if (!decoded(tcs::mcap_decode_schema(r.body, &s, &known), &known, r, "summary Schema"))
				return false;
			out_.summary_schemas.push_back(s);
			return true;
		}
		case tcs::mcap_channel: {
			tcs::McapChannel c;
			if (!decoded(tcs::mcap_decode_channel(r.body, &c, &known), &known, r, "summary Channel"))
				return false;
			out_.summary_channels.push_back(c);
			return true;
		}
		case tcs::mcap_statistics:
			return decoded(tcs::mcap_decode_statistics(r.body, &out_.stats, &known), &known, r, "Statistics");
		case tcs::mcap_chunk_index: {
			tcs::McapChunkIndex ci;
			if (!decoded(tcs::mcap_decode_chunk_index(r.body, &ci, &known), &known, r, "Chunk Index"))
				return false;
			out_.chunk_indexes.push_back(ChunkInfo{ ci.chunk_start_offset, ci.chunk_length, ci.message_start_time,
								ci.message_end_time, ci.uncompressed_size, ci.compressed_size,
								std::string(ci.compression), ci.message_index_offsets,
								ci.message_index_length, 0 });
			return true;
		}
		default:
			return problem("opcode 0x%02x not expected in the summary", r.op);
		}
	}

	// The summary describes what the data section holds.
	void cross_check()
	{
		if (out_.chunk_indexes.size() != out_.chunks.size())
			return (void)problem("%zu Chunk Index records for %zu chunks", out_.chunk_indexes.size(),
					     out_.chunks.size());
		for (size_t i = 0; i < out_.chunks.size(); i++) {
			ChunkInfo c = out_.chunks[i];
			c.messages = 0; // a Chunk Index does not count them
			if (!(out_.chunk_indexes[i] == c))
				return (void)problem("Chunk Index %zu does not match its chunk", i);
		}
		std::map<uint16_t, tcs::McapSchema> ss;
		for (const tcs::McapSchema &s : out_.summary_schemas)
			if (!ss.emplace(s.id, s).second)
				return (void)problem("schema %u twice in the summary", s.id);
		for (const auto &[id, s] : out_.schemas)
			if (!ss.count(id) || !(ss[id] == s))
				return (void)problem("schema %u differs between data and summary", id);
		std::map<uint16_t, tcs::McapChannel> cs;
		for (const tcs::McapChannel &c : out_.summary_channels) {
			if (!cs.emplace(c.id, c).second)
				return (void)problem("channel %u twice in the summary", c.id);
			if (c.schema_id && !ss.count(c.schema_id))
				return (void)problem("summary channel %u's schema is not in the summary", c.id);
		}
		for (const auto &[id, c] : out_.channels)
			if (!cs.count(id) || !(cs[id] == c))
				return (void)problem("channel %u differs between data and summary", id);
		tcs::McapStatistics want;
		want.message_count = out_.messages.size();
		want.schema_count = uint16_t(ss.size());
		want.channel_count = uint32_t(cs.size());
		want.chunk_count = uint32_t(out_.chunks.size());
		for (const auto &[id, c] : cs)
			want.channel_message_counts[id] = 0;
		if (!out_.messages.empty())
			want.message_start_time = UINT64_MAX;
		for (const Msg &m : out_.messages) {
			want.channel_message_counts[m.channel]++;
			want.message_start_time = std::min(want.message_start_time, m.log);
			want.message_end_time = std::max(want.message_end_time, m.log);
		}
		if (!(want == out_.stats))
			return (void)problem("Statistics do not match the file");
	}

	const std::string &f_;
	ReadBack &out_;
	tcs::McapChunkUnpacker unpacker_;
	Open open_;
	bool in_chunk_ = false;
	size_t seen_ = 0; // messages in the chunks so far
};

} // namespace

uint32_t ref_crc32(const void *data, size_t size)
{
	const uint8_t *p = static_cast<const uint8_t *>(data);
	uint32_t c = 0xFFFFFFFFu;
	for (size_t i = 0; i < size; i++) {
		c ^= p[i];
		for (int k = 0; k < 8; k++)
			c = (c & 1) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
	}
	return ~c;
}

ReadBack read_back(const std::string &file)
{
	ReadBack out;
	tcs::McapReader reader;
	if (tcs::Status s = reader.open_bytes("file", file); !s) {
		out.error = s.error().message;
		return out;
	}
	out.profile = reader.profile();
	out.library = reader.library();
	for (;;) {
		tcs::McapMessage m;
		auto more = reader.next(&m);
		if (!more) {
			out.error = more.error().message;
			return out;
		}
		if (!*more)
			break;
		out.messages.push_back(Msg{ m.channel->id, m.sequence, m.log_time, m.publish_time, std::string(m.data) });
	}
	out.schemas = reader.schemas();
	out.channels = reader.channels();
	Layout(file, out).check();
	if (!out.error.empty())
		return out;
	// The reader and the layout agree on where the file ends, and on
	// what its chunks hold: every message read was in one.
	if (out.complete == reader.truncated())
		out.error = out.complete ? "complete, but the reader found it truncated" : "the reader found no end";
	else if ((out.messages_after_chunk.empty() ? 0 : out.messages_after_chunk.back()) != out.messages.size())
		out.error = "the reader read messages outside the chunks";
	return out;
}

ReadBack read_back_ok(const std::string &file, bool complete)
{
	ReadBack r = read_back(file);
	if (!r.error.empty()) {
		print_error("MCAP problem: %s\n", r.error.c_str());
		fail();
	}
	if (r.complete != complete) {
		print_error("file is %scomplete, expected %scomplete\n", r.complete ? "" : "not ", complete ? "" : "not ");
		fail();
	}
	return r;
}

void expect_messages(const ReadBack &r, const std::vector<Msg> &want, size_t count)
{
	assert_true(count <= want.size());
	if (r.messages.size() != count || !std::equal(r.messages.begin(), r.messages.end(), want.begin())) {
		print_error("read %zu messages, expected the first %zu written\n", r.messages.size(), count);
		fail();
	}
}

} // namespace mcap_check
