// Unit tests for trace/mcap_writer: its CRC-32, and the bytes of the
// files it writes, read back by an independent parser that follows the MCAP
// specification (records, chunks decompressed and CRC-checked, message
// indexes, Data End, summary groups, summary offsets, footer) — complete
// files, files cut short anywhere (a reader scanning from the start must
// find every complete chunk), a writer stopped by a full file system, and
// one SIGKILLed while writing.
//
// The files go to a temporary directory that is removed afterwards, unless
// TCS_MCAP_TEST_DIR names a directory to keep them in (tests/mcap/check.mjs
// reads them with the reference TypeScript readers).
#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "result_checks.h"

#include "mcap_crc32.h"
#include "mcap_writer.h"

namespace {

using tcs::McapCompression;
using tcs::McapWriter;
using tcs::McapWriterOptions;

std::string g_dir;
bool g_keep = false;
std::vector<std::string> g_files;

std::string test_path(const std::string &name)
{
	std::string p = g_dir + "/" + name;
	g_files.push_back(p);
	return p;
}

std::vector<uint8_t> slurp(const std::string &path)
{
	std::vector<uint8_t> out;
	FILE *f = std::fopen(path.c_str(), "rb");
	assert_non_null(f);
	uint8_t buf[65536];
	size_t n;
	while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
		out.insert(out.end(), buf, buf + n);
	std::fclose(f);
	return out;
}

void spit(const std::string &path, const uint8_t *data, size_t size)
{
	FILE *f = std::fopen(path.c_str(), "wb");
	assert_non_null(f);
	assert_int_equal(std::fwrite(data, 1, size, f), size);
	assert_int_equal(std::fclose(f), 0);
}


// The textbook bit-at-a-time CRC-32, to check the writer's table-driven one.
uint32_t ref_crc32(const uint8_t *p, size_t n)
{
	uint32_t c = 0xFFFFFFFFu;
	for (size_t i = 0; i < n; i++) {
		c ^= p[i];
		for (int k = 0; k < 8; k++)
			c = (c & 1) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
	}
	return ~c;
}

// ---- An independent reader of MCAP bytes ----

const uint8_t kMagic[8] = { 0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n' };

// Bounds-checked little-endian reads; any overrun clears ok().
class Bytes {
public:
	Bytes(const uint8_t *p, size_t n) : p_(p), n_(n) {}
	bool ok() const { return ok_; }
	size_t pos() const { return pos_; }
	size_t left() const { return ok_ ? n_ - pos_ : 0; }
	const uint8_t *here() const { return p_ + pos_; }
	uint64_t le(int k)
	{
		if (!ok_ || n_ - pos_ < size_t(k)) {
			ok_ = false;
			return 0;
		}
		uint64_t v = 0;
		for (int i = 0; i < k; i++)
			v |= uint64_t(p_[pos_ + i]) << (8 * i);
		pos_ += k;
		return v;
	}
	uint8_t u8() { return uint8_t(le(1)); }
	uint16_t u16() { return uint16_t(le(2)); }
	uint32_t u32() { return uint32_t(le(4)); }
	uint64_t u64() { return le(8); }
	std::string take(uint64_t k)
	{
		if (!ok_ || n_ - pos_ < k) {
			ok_ = false;
			return {};
		}
		std::string s(reinterpret_cast<const char *>(p_ + pos_), size_t(k));
		pos_ += size_t(k);
		return s;
	}
	std::string str() { return take(u32()); }

private:
	const uint8_t *p_;
	size_t n_;
	size_t pos_ = 0;
	bool ok_ = true;
};

struct Msg {
	uint16_t channel;
	uint32_t seq;
	uint64_t log, pub;
	std::string data;
	bool operator==(const Msg &) const = default;
};
struct SchemaRec {
	uint16_t id;
	std::string name, encoding, data;
	bool operator==(const SchemaRec &) const = default;
};
struct ChannelRec {
	uint16_t id, schema_id;
	std::string topic, encoding;
	std::map<std::string, std::string> metadata;
	bool operator==(const ChannelRec &) const = default;
};
// A chunk as found in the data section, or as its Chunk Index describes it.
struct ChunkInfo {
	uint64_t offset = 0, length = 0, start = 0, end = 0, usize = 0, csize = 0;
	std::string compression;
	std::map<uint16_t, uint64_t> mi_offsets;
	uint64_t mi_length = 0;
	bool operator==(const ChunkInfo &) const = default;
};
struct Stats {
	uint64_t messages = 0;
	uint16_t schemas = 0;
	uint32_t channels = 0, attachments = 0, metadata = 0, chunks = 0;
	uint64_t start = 0, end = 0;
	std::map<uint16_t, uint64_t> per_channel;
	bool operator==(const Stats &) const = default;
};

struct Parsed {
	std::string error;     // the first problem, or empty
	bool complete = false; // Data End, summary, footer and magic all there
	std::string profile, library;
	std::vector<Msg> messages;
	std::map<uint16_t, SchemaRec> schemas;
	std::map<uint16_t, ChannelRec> channels;
	std::vector<ChunkInfo> chunks;
	std::vector<size_t> messages_after_chunk; // messages in chunks 0..i
	// The summary, for complete files.
	std::vector<SchemaRec> summary_schemas;
	std::vector<ChannelRec> summary_channels;
	std::vector<ChunkInfo> chunk_indexes;
	Stats stats;
};

bool parse_schema(Bytes &b, SchemaRec &s)
{
	s.id = b.u16();
	s.name = b.str();
	s.encoding = b.str();
	s.data = b.str();
	return b.ok() && b.left() == 0;
}

bool parse_channel(Bytes &b, ChannelRec &c)
{
	c.id = b.u16();
	c.schema_id = b.u16();
	c.topic = b.str();
	c.encoding = b.str();
	std::string map = b.str();
	Bytes m(reinterpret_cast<const uint8_t *>(map.data()), map.size());
	while (m.ok() && m.left() > 0) {
		std::string k = m.str();
		c.metadata[k] = m.str();
	}
	return b.ok() && m.ok() && b.left() == 0;
}

class Parser {
public:
	explicit Parser(const std::vector<uint8_t> &f) : f_(f) {}

	Parsed run()
	{
		data_section();
		if (out_.error.empty() && out_.complete)
			cross_check();
		return std::move(out_);
	}

private:
	struct Record {
		uint8_t op;
		size_t offset;
		uint64_t len;
		const uint8_t *body;
	};
	// Per chunk: each channel's (log time, offset) pairs, and which
	// channels its Message Index records have covered.
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

	// The record at pos, if all of it is there.
	bool record_at(size_t pos, size_t end, Record &r)
	{
		if (end - pos < 9)
			return false;
		Bytes b(f_.data() + pos, 9);
		r.op = b.u8();
		r.len = b.u64();
		if (r.len > end - pos - 9)
			return false;
		r.offset = pos;
		r.body = f_.data() + pos + 9;
		return true;
	}

	void data_section()
	{
		if (f_.size() < 8) // a file cut before its magic is complete holds nothing
			return;
		if (!std::equal(kMagic, kMagic + 8, f_.begin()))
			return (void)problem("no leading magic");
		Record r;
		size_t pos = 8;
		if (!record_at(pos, f_.size(), r))
			return;
		if (r.op != 0x01)
			return (void)problem("first record has opcode 0x%02x, not Header", r.op);
		Bytes h(r.body, r.len);
		out_.profile = h.str();
		out_.library = h.str();
		if (!h.ok() || h.left())
			return (void)problem("malformed Header");
		pos += 9 + r.len;

		while (record_at(pos, f_.size(), r)) {
			pos += 9 + r.len;
			if (r.op == 0x06) {
				if (!close_chunk() || !chunk(r))
					return;
			} else if (r.op == 0x07) {
				if (!message_index(r))
					return;
			} else if (r.op == 0x0F) {
				if (!close_chunk())
					return;
				Bytes b(r.body, r.len);
				uint32_t crc = b.u32();
				if (!b.ok() || b.left())
					return (void)problem("malformed Data End");
				if (crc != ref_crc32(f_.data(), r.offset))
					return (void)problem("data section CRC 0x%08x is wrong", crc);
				summary(pos);
				return;
			} else {
				return (void)problem("opcode 0x%02x at %zu: not expected in this writer's data section", r.op,
						  r.offset);
			}
		}
		// Cut short: the last chunk's Message Index records may be missing.
	}

	bool chunk(const Record &r)
	{
		ChunkInfo c;
		Bytes b(r.body, r.len);
		c.offset = r.offset;
		c.length = 9 + r.len;
		c.start = b.u64();
		c.end = b.u64();
		c.usize = b.u64();
		uint32_t crc = b.u32();
		c.compression = b.str();
		c.csize = b.u64();
		if (!b.ok() || b.left() != c.csize)
			return problem("chunk at %zu: its sizes do not add up", r.offset);
		std::string raw;
		if (c.compression == "zstd") {
			raw.resize(c.usize);
			size_t z = ZSTD_decompress(raw.data(), raw.size(), b.here(), c.csize);
			if (ZSTD_isError(z) || z != c.usize)
				return problem("chunk at %zu: zstd data does not decompress to %lu bytes", r.offset,
					    (unsigned long)c.usize);
		} else if (c.compression.empty()) {
			if (c.csize != c.usize)
				return problem("uncompressed chunk at %zu: sizes differ", r.offset);
			raw.assign(reinterpret_cast<const char *>(b.here()), c.csize);
		} else {
			return problem("chunk at %zu: compression '%s'", r.offset, c.compression.c_str());
		}
		if (crc != ref_crc32(reinterpret_cast<const uint8_t *>(raw.data()), raw.size()))
			return problem("chunk at %zu: CRC 0x%08x of the uncompressed records is wrong", r.offset, crc);

		open_ = Open{};
		uint64_t lo = UINT64_MAX, hi = 0;
		Bytes in(reinterpret_cast<const uint8_t *>(raw.data()), raw.size());
		while (in.ok() && in.left() > 0) {
			size_t at = in.pos();
			uint8_t op = in.u8();
			uint64_t len = in.u64();
			std::string body = in.take(len);
			if (!in.ok())
				return problem("chunk at %zu: record at %zu overruns the chunk", r.offset, at);
			Bytes rb(reinterpret_cast<const uint8_t *>(body.data()), body.size());
			if (op == 0x03) {
				SchemaRec s;
				if (!parse_schema(rb, s) || s.id == 0)
					return problem("chunk at %zu: bad Schema at %zu", r.offset, at);
				auto [it, fresh] = out_.schemas.emplace(s.id, s);
				if (!fresh && !(it->second == s))
					return problem("schema %u redefined differently", s.id);
			} else if (op == 0x04) {
				ChannelRec ch;
				if (!parse_channel(rb, ch))
					return problem("chunk at %zu: bad Channel at %zu", r.offset, at);
				if (ch.schema_id && !out_.schemas.count(ch.schema_id))
					return problem("channel %u before its schema %u", ch.id, ch.schema_id);
				auto [it, fresh] = out_.channels.emplace(ch.id, ch);
				if (!fresh && !(it->second == ch))
					return problem("channel %u redefined differently", ch.id);
			} else if (op == 0x05) {
				Msg m;
				m.channel = rb.u16();
				m.seq = rb.u32();
				m.log = rb.u64();
				m.pub = rb.u64();
				m.data = rb.take(rb.left());
				if (!rb.ok())
					return problem("chunk at %zu: short Message at %zu", r.offset, at);
				if (!out_.channels.count(m.channel))
					return problem("message on channel %u before its Channel record", m.channel);
				open_.entries[m.channel].push_back({ m.log, at });
				lo = std::min(lo, m.log);
				hi = std::max(hi, m.log);
				out_.messages.push_back(std::move(m));
			} else {
				return problem("chunk at %zu: opcode 0x%02x inside a chunk", r.offset, op);
			}
		}
		if (open_.entries.empty())
			lo = 0;
		if (c.start != lo || c.end != hi)
			return problem("chunk at %zu: times [%lu, %lu], messages [%lu, %lu]", r.offset,
				    (unsigned long)c.start, (unsigned long)c.end, (unsigned long)lo, (unsigned long)hi);
		out_.chunks.push_back(c);
		out_.messages_after_chunk.push_back(out_.messages.size());
		in_chunk_ = true;
		return true;
	}

	bool message_index(const Record &r)
	{
		if (!in_chunk_)
			return problem("Message Index at %zu follows no chunk", r.offset);
		ChunkInfo &c = out_.chunks.back();
		Bytes b(r.body, r.len);
		uint16_t id = b.u16();
		uint32_t bytes = b.u32();
		if (!b.ok() || b.left() != bytes || bytes % 16)
			return problem("malformed Message Index at %zu", r.offset);
		std::vector<std::pair<uint64_t, uint64_t>> got;
		while (b.left())
			got.push_back({ b.u64(), b.u64() });
		for (size_t i = 1; i < got.size(); i++)
			if (got[i].first < got[i - 1].first)
				return problem("Message Index at %zu not in log time order", r.offset);
		auto it = open_.entries.find(id);
		if (it == open_.entries.end() || !open_.indexed.insert(id).second)
			return problem("Message Index at %zu: channel %u has no messages here, or a second index", r.offset,
				    id);
		auto want = it->second;
		std::sort(want.begin(), want.end());
		std::sort(got.begin(), got.end());
		if (got != want)
			return problem("Message Index at %zu does not point at channel %u's messages", r.offset, id);
		c.mi_offsets[id] = r.offset;
		c.mi_length += 9 + r.len;
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

	void summary(size_t summary_start)
	{
		const size_t footer_len = 9 + 20, n = f_.size();
		if (n < summary_start + footer_len + 8 || !std::equal(kMagic, kMagic + 8, f_.end() - 8))
			return; // cut after Data End
		const size_t footer_at = n - 8 - footer_len;
		Bytes ft(f_.data() + footer_at, footer_len);
		uint8_t op = ft.u8();
		uint64_t len = ft.u64();
		uint64_t s_start = ft.u64(), so_start = ft.u64();
		uint32_t crc = ft.u32();
		if (op != 0x02 || len != 20)
			return (void)problem("no Footer before the closing magic");
		if (s_start != summary_start)
			return (void)problem("footer's summary_start %lu, but Data End ends at %zu", (unsigned long)s_start,
					  summary_start);
		if (so_start <= s_start || so_start > footer_at)
			return (void)problem("footer's summary_offset_start %lu is outside the summary", (unsigned long)so_start);
		if (crc != ref_crc32(f_.data() + s_start, footer_at + 9 + 16 - s_start))
			return (void)problem("summary CRC 0x%08x is wrong", crc);

		// Groups of one opcode each, in the summary; then their offsets.
		std::map<uint8_t, std::pair<uint64_t, uint64_t>> groups; // opcode -> start, length
		uint8_t last = 0;
		Record r;
		size_t pos = s_start;
		while (pos < so_start) {
			if (!record_at(pos, so_start, r))
				return (void)problem("summary record at %zu overruns the summary", pos);
			pos += 9 + r.len;
			if (r.op != last && groups.count(r.op))
				return (void)problem("summary opcode 0x%02x in two groups", r.op);
			last = r.op;
			auto &g = groups[r.op];
			if (g.second == 0)
				g.first = r.offset;
			g.second += 9 + r.len;
			Bytes b(r.body, r.len);
			if (r.op == 0x03) {
				SchemaRec s;
				if (!parse_schema(b, s))
					return (void)problem("bad summary Schema");
				out_.summary_schemas.push_back(s);
			} else if (r.op == 0x04) {
				ChannelRec c;
				if (!parse_channel(b, c))
					return (void)problem("bad summary Channel");
				out_.summary_channels.push_back(c);
			} else if (r.op == 0x0B) {
				Stats &s = out_.stats;
				s.messages = b.u64();
				s.schemas = b.u16();
				s.channels = b.u32();
				s.attachments = b.u32();
				s.metadata = b.u32();
				s.chunks = b.u32();
				s.start = b.u64();
				s.end = b.u64();
				uint32_t bytes = b.u32();
				if (!b.ok() || b.left() != bytes || bytes % 10)
					return (void)problem("bad Statistics");
				while (b.left()) {
					uint16_t id = b.u16();
					s.per_channel[id] = b.u64();
				}
			} else if (r.op == 0x08) {
				ChunkInfo c;
				c.start = b.u64();
				c.end = b.u64();
				c.offset = b.u64();
				c.length = b.u64();
				uint32_t bytes = b.u32();
				for (uint32_t i = 0; i < bytes / 10 && b.ok(); i++) {
					uint16_t id = b.u16();
					c.mi_offsets[id] = b.u64();
				}
				c.mi_length = b.u64();
				c.compression = b.str();
				c.csize = b.u64();
				c.usize = b.u64();
				if (!b.ok() || b.left() || bytes % 10)
					return (void)problem("bad Chunk Index at %zu", r.offset);
				out_.chunk_indexes.push_back(c);
			} else {
				return (void)problem("opcode 0x%02x not expected in the summary", r.op);
			}
		}
		std::map<uint8_t, std::pair<uint64_t, uint64_t>> offsets;
		for (pos = so_start; pos < footer_at;) {
			if (!record_at(pos, footer_at, r) || r.op != 0x0E || r.len != 17)
				return (void)problem("bad Summary Offset record at %zu", pos);
			pos += 9 + r.len;
			Bytes b(r.body, r.len);
			uint8_t g = b.u8();
			uint64_t start = b.u64();
			offsets[g] = { start, b.u64() };
		}
		if (offsets != groups)
			return (void)problem("Summary Offset records do not match the summary's groups");
		out_.complete = true;
	}

	// The summary describes what the data section holds.
	void cross_check()
	{
		if (out_.chunk_indexes != out_.chunks)
			return (void)problem("Chunk Index records do not match the chunks");
		std::map<uint16_t, SchemaRec> ss;
		for (const SchemaRec &s : out_.summary_schemas)
			if (!ss.emplace(s.id, s).second)
				return (void)problem("schema %u twice in the summary", s.id);
		for (const auto &[id, s] : out_.schemas)
			if (!ss.count(id) || !(ss[id] == s))
				return (void)problem("schema %u differs between data and summary", id);
		std::map<uint16_t, ChannelRec> cs;
		for (const ChannelRec &c : out_.summary_channels) {
			if (!cs.emplace(c.id, c).second)
				return (void)problem("channel %u twice in the summary", c.id);
			if (c.schema_id && !ss.count(c.schema_id))
				return (void)problem("summary channel %u's schema is not in the summary", c.id);
		}
		for (const auto &[id, c] : out_.channels)
			if (!cs.count(id) || !(cs[id] == c))
				return (void)problem("channel %u differs between data and summary", id);
		Stats want;
		want.messages = out_.messages.size();
		want.schemas = uint16_t(ss.size());
		want.channels = uint32_t(cs.size());
		want.chunks = uint32_t(out_.chunks.size());
		for (const auto &[id, c] : cs)
			want.per_channel[id] = 0;
		if (!out_.messages.empty())
			want.start = UINT64_MAX;
		for (const Msg &m : out_.messages) {
			want.per_channel[m.channel]++;
			want.start = std::min(want.start, m.log);
			want.end = std::max(want.end, m.log);
		}
		if (!(want == out_.stats))
			return (void)problem("Statistics do not match the file");
	}

	const std::vector<uint8_t> &f_;
	Parsed out_;
	Open open_;
	bool in_chunk_ = false;
};

Parsed parse(const std::vector<uint8_t> &f) { return Parser(f).run(); }

Parsed parse_ok(const std::vector<uint8_t> &f, bool complete)
{
	Parsed p = parse(f);
	if (!p.error.empty()) {
		print_error("MCAP problem: %s\n", p.error.c_str());
		fail();
	}
	if (p.complete != complete) {
		print_error("file is %scomplete, expected %scomplete\n", p.complete ? "" : "not ",
			    complete ? "" : "not ");
		fail();
	}
	return p;
}

// ---- What the tests write ----

const char kSliceSchema[] = R"({"type":"object","properties":{"controller":{"type":"string"},)"
			    R"("start_ns":{"type":"integer"},"end_ns":{"type":"integer"}}})";
const char kClockSchema[] = R"({"type":"object","properties":{"t_ns":{"type":"integer"}}})";

// Three channels, two sharing a schema, and deterministic JSON messages of
// varying sizes on them. The writer numbers each channel's messages; so
// does the expectation.
struct Sample {
	uint16_t ch[3];
	uint32_t seq[3] = { 0, 0, 0 };
	std::vector<Msg> expected;

	void setup(McapWriter &w)
	{
		uint16_t slice = MUST(w.add_schema("tcs.Slice", kSliceSchema));
		uint16_t clock = MUST(w.add_schema("tcs.Clock", kClockSchema));
		ch[0] = MUST(w.add_channel("/clock", clock));
		ch[1] = MUST(w.add_channel("/tcs/slices/a", slice, { { "controller", "pendulum_pd" } }));
		ch[2] = MUST(w.add_channel("/tcs/slices/b", slice));
	}

	// Message i (call in order of i).
	Msg next(int i)
	{
		int k = i % 5 == 0 ? 0 : 1 + i % 2;
		uint64_t t = 1'000'000 + 1000 * uint64_t(i);
		std::string json = k == 0 ? "{\"t_ns\":" + std::to_string(t) + "}"
					  : "{\"controller\":\"c" + std::to_string(k) + std::string(i % 23, 'x') +
						    "\",\"start_ns\":" + std::to_string(t) + ",\"end_ns\":" + std::to_string(t + 500) +
						    "}";
		return Msg{ ch[k], seq[k]++, t, t + 7, json };
	}

	void write(McapWriter &w, int from, int to)
	{
		for (int i = from; i < to; i++) {
			Msg m = next(i);
			CHECK_OK(w.write(m.channel, m.log, m.pub, m.data));
			expected.push_back(std::move(m));
		}
	}
};

void expect_messages(const Parsed &p, const std::vector<Msg> &want, size_t count)
{
	assert_true(count <= want.size());
	if (p.messages.size() != count || !std::equal(p.messages.begin(), p.messages.end(), want.begin())) {
		print_error("read %zu messages, expected the first %zu written\n", p.messages.size(), count);
		fail();
	}
}

// ---- Tests ----

void test_crc32(void **)
{
	const char *s = "123456789";
	assert_int_equal(tcs::mcap_crc32(0, s, 9), 0xCBF43926u);
	assert_int_equal(tcs::mcap_crc32(0, s, 0), 0u);
	assert_int_equal(tcs::mcap_crc32(tcs::mcap_crc32(0, s, 4), s + 4, 5), 0xCBF43926u);

	std::vector<uint8_t> data(1 << 20);
	uint64_t x = 88172645463325252ull;
	for (uint8_t &b : data) {
		x ^= x << 13, x ^= x >> 7, x ^= x << 17;
		b = uint8_t(x);
	}
	for (size_t off = 0; off < 8; off++)
		for (size_t len = 0; len < 80; len++)
			assert_int_equal(tcs::mcap_crc32(0, data.data() + off, len), ref_crc32(data.data() + off, len));
	uint32_t whole = ref_crc32(data.data(), data.size());
	assert_int_equal(tcs::mcap_crc32(0, data.data(), data.size()), whole);
	uint32_t pieces = 0;
	for (size_t at = 0, step = 1; at < data.size(); at += step, step = step * 3 + 1)
		pieces = tcs::mcap_crc32(pieces, data.data() + at, std::min(step, data.size() - at));
	assert_int_equal(pieces, whole);
}

void check_sample_file(McapCompression compression, const char *name)
{
	std::string path = test_path(name);
	McapWriter w(McapWriterOptions{ .chunk_size = 4096, .compression = compression });
	CHECK_OK(w.open(path, "x-tcs", "tcs test"));
	Sample s;
	s.setup(w);
	s.write(w, 0, 3000);
	CHECK_OK(w.close());
	assert_false(w.is_open());

	std::vector<uint8_t> f = slurp(path);
	Parsed p = parse_ok(f, true);
	assert_string_equal(p.profile.c_str(), "x-tcs");
	assert_string_equal(p.library.c_str(), "tcs test");
	expect_messages(p, s.expected, s.expected.size());
	assert_int_equal(p.chunks.size(), w.chunk_count());
	assert_true(p.chunks.size() > 20);
	for (size_t i = 0; i < p.chunks.size(); i++) {
		const ChunkInfo &c = p.chunks[i];
		assert_string_equal(c.compression.c_str(), compression == McapCompression::zstd ? "zstd" : "");
		// Full chunks end with the message that reached 4096 bytes:
		// at most one message, its channel and its schema beyond.
		if (i + 1 < p.chunks.size()) {
			assert_true(c.usize >= 4096);
			assert_true(c.usize < 4096 + 600);
		}
	}
	assert_int_equal(p.summary_schemas.size(), 2);
	assert_int_equal(p.summary_channels.size(), 3);
	assert_string_equal(p.summary_channels[1].topic.c_str(), "/tcs/slices/a");
	assert_string_equal(p.summary_channels[1].encoding.c_str(), "json");
	assert_string_equal(p.summary_channels[1].metadata["controller"].c_str(), "pendulum_pd");
	assert_string_equal(p.summary_schemas[0].encoding.c_str(), "jsonschema");
	assert_int_equal(p.stats.messages, 3000);
	assert_int_equal(w.file_bytes(), f.size());
}

void test_zstd_file(void **) { check_sample_file(McapCompression::zstd, "zstd.mcap"); }
void test_uncompressed_file(void **) { check_sample_file(McapCompression::none, "uncompressed.mcap"); }

// Default options: 1 MiB chunks, zstd.
void test_default_chunks(void **)
{
	std::string path = test_path("default.mcap");
	McapWriter w;
	CHECK_OK(w.open(path));
	Sample s;
	s.setup(w);
	s.write(w, 0, 40000); // about 3.3 MB of records
	CHECK_OK(w.close());
	Parsed p = parse_ok(slurp(path), true);
	expect_messages(p, s.expected, s.expected.size());
	assert_int_equal(p.chunks.size(), 4);
	for (size_t i = 0; i + 1 < p.chunks.size(); i++) {
		assert_true(p.chunks[i].usize >= (1u << 20) && p.chunks[i].usize < (1u << 20) + 600);
		assert_true(p.chunks[i].csize < p.chunks[i].usize / 4);
	}
}

// Chunks zstd does not shrink are stored as they are, next to compressed
// ones in the same file.
void test_incompressible_chunks(void **)
{
	std::string path = test_path("mixed.mcap");
	McapWriter w(McapWriterOptions{ .chunk_size = 8192 });
	CHECK_OK(w.open(path));
	Sample s;
	s.setup(w);
	uint16_t noise_schema = MUST(w.add_schema("noise", "x-tcs-bytes", ""));
	uint16_t noise = MUST(w.add_channel("/noise", "x-tcs-bytes", noise_schema));
	std::string buf(3000, '\0');
	uint64_t x = 1;
	for (int i = 0; i < 10; i++) {
		for (char &c : buf) {
			x = x * 6364136223846793005ull + 1442695040888963407ull;
			c = char(x >> 56);
		}
		CHECK_OK(w.write(noise, 5000 + i, 5000 + i, buf));
		s.expected.push_back(Msg{ noise, uint32_t(i), uint64_t(5000 + i), uint64_t(5000 + i), buf });
	}
	CHECK_OK(w.flush());
	s.write(w, 0, 500);
	CHECK_OK(w.close());
	Parsed p = parse_ok(slurp(path), true);
	expect_messages(p, s.expected, s.expected.size());
	assert_string_equal(p.chunks.front().compression.c_str(), "");
	assert_string_equal(p.chunks.back().compression.c_str(), "zstd");
}

// Log times out of order within a chunk: the Message Index records are
// still sorted by time (the parser checks), the chunk's times are its
// extremes.
void test_out_of_order_times(void **)
{
	std::string path = test_path("out_of_order.mcap");
	McapWriter w(McapWriterOptions{ .chunk_size = 2000 });
	CHECK_OK(w.open(path));
	uint16_t sc = MUST(w.add_schema("tcs.Clock", kClockSchema));
	uint16_t a = MUST(w.add_channel("/a", sc));
	uint16_t b = MUST(w.add_channel("/b", sc));
	std::vector<Msg> want;
	uint32_t seq[2] = { 0, 0 };
	uint64_t last = 0;
	for (uint64_t i = 0; i < 200; i++) {
		uint64_t t = (i * 7919) % 1000 + 10; // a permutation of times
		last = std::max(last, t);
		uint16_t ch = i % 3 ? a : b;
		std::string json = "{\"t_ns\":" + std::to_string(t) + "}";
		CHECK_OK(w.write(ch, t, 0, json));
		want.push_back(Msg{ ch, seq[ch == b]++, t, 0, json });
	}
	CHECK_OK(w.close());
	Parsed p = parse_ok(slurp(path), true);
	expect_messages(p, want, want.size());
	assert_int_equal(p.stats.start, 10);
	assert_int_equal(p.stats.end, last);
}

// A file cut anywhere reads, from the start, as its complete chunks.
void test_truncated(void **)
{
	std::string path = test_path("whole.mcap");
	McapWriter w(McapWriterOptions{ .chunk_size = 4096 });
	CHECK_OK(w.open(path));
	Sample s;
	s.setup(w);
	s.write(w, 0, 1000);
	CHECK_OK(w.close());
	std::vector<uint8_t> f = slurp(path);
	Parsed whole = parse_ok(f, true);
	assert_true(whole.chunks.size() > 6);

	// Messages in the first k chunks.
	auto upto = [&](size_t k) { return k ? whole.messages_after_chunk[k - 1] : 0; };
	auto cut = [&](size_t at) { return parse_ok(std::vector<uint8_t>(f.begin(), f.begin() + at), false); };

	const ChunkInfo &c3 = whole.chunks[3];
	// In the middle of chunk 3's record: chunks 0-2.
	Parsed p = cut(c3.offset + c3.length / 2);
	assert_int_equal(p.chunks.size(), 3);
	expect_messages(p, s.expected, upto(3));
	spit(test_path("truncated.mcap"), f.data(), c3.offset + c3.length / 2);
	// One byte into its record, and one byte short of its end.
	expect_messages(cut(c3.offset + 1), s.expected, upto(3));
	expect_messages(cut(c3.offset + c3.length - 1), s.expected, upto(3));
	// Right after it, before its indexes; inside them; after them.
	expect_messages(cut(c3.offset + c3.length), s.expected, upto(4));
	expect_messages(cut(c3.offset + c3.length + c3.mi_length / 2), s.expected, upto(4));
	expect_messages(cut(c3.offset + c3.length + c3.mi_length), s.expected, upto(4));
	// Nothing but the magic, part of the header.
	expect_messages(cut(8), s.expected, 0);
	expect_messages(cut(15), s.expected, 0);
	expect_messages(cut(3), s.expected, 0);
	// All chunks, cut in the summary or the footer.
	expect_messages(cut(f.size() - 40), s.expected, s.expected.size());
	expect_messages(cut(f.size() - 1), s.expected, s.expected.size());
	// Every cut point in the first chunks.
	for (size_t at = 0; at < whole.chunks[2].offset; at += 37)
		(void)cut(at);
}

// flush() writes the chunk so far: the file reads back while still open.
void test_flush(void **)
{
	std::string path = test_path("flush.mcap");
	McapWriter w;
	CHECK_OK(w.open(path));
	Sample s;
	s.setup(w);
	s.write(w, 0, 5);
	assert_int_equal(w.chunk_count(), 0);
	assert_true(w.pending_bytes() > 0);
	CHECK_OK(w.flush());
	assert_int_equal(w.chunk_count(), 1);
	assert_int_equal(w.pending_bytes(), 0);
	CHECK_OK(w.flush()); // nothing new: no empty chunk
	assert_int_equal(w.chunk_count(), 1);
	std::vector<uint8_t> f = slurp(path);
	assert_int_equal(f.size(), w.file_bytes());
	expect_messages(parse_ok(f, false), s.expected, 5);
	s.write(w, 5, 10);
	CHECK_OK(w.close());
	Parsed p = parse_ok(slurp(path), true);
	expect_messages(p, s.expected, 10);
	assert_int_equal(p.chunks.size(), 2);
}

void test_empty_files(void **)
{
	std::string path = test_path("empty.mcap");
	McapWriter w;
	CHECK_OK(w.open(path));
	CHECK_OK(w.close());
	Parsed p = parse_ok(slurp(path), true);
	assert_int_equal(p.messages.size(), 0);
	assert_int_equal(p.chunks.size(), 0);
	assert_string_equal(p.library.c_str(), "tcs");

	// Reusing the writer for another file.
	path = test_path("no_messages.mcap");
	CHECK_OK(w.open(path));
	Sample s;
	s.setup(w);
	CHECK_OK(w.close());
	p = parse_ok(slurp(path), true);
	assert_int_equal(p.messages.size(), 0);
	assert_int_equal(p.summary_channels.size(), 3);
	assert_int_equal(p.stats.per_channel.size(), 3);
}

// A message larger than a chunk makes a chunk of its own.
void test_large_message(void **)
{
	std::string path = test_path("large.mcap");
	McapWriter w;
	CHECK_OK(w.open(path));
	Sample s;
	s.setup(w);
	s.write(w, 0, 10);
	std::string big = "{\"controller\":\"" + std::string(3 << 20, 'y') + "\"}";
	CHECK_OK(w.write(s.ch[1], 99'000'000, 99'000'000, big));
	s.expected.push_back(Msg{ s.ch[1], s.seq[1]++, 99'000'000, 99'000'000, big });
	assert_int_equal(w.chunk_count(), 1);
	s.write(w, 10, 20);
	CHECK_OK(w.close());
	Parsed p = parse_ok(slurp(path), true);
	expect_messages(p, s.expected, s.expected.size());
	assert_int_equal(p.chunks.size(), 2);
}

void test_schema_ids(void **)
{
	McapWriter w;
	CHECK_OK(w.open(test_path("ids.mcap")));
	uint16_t a = MUST(w.add_schema("A", kClockSchema));
	uint16_t b = MUST(w.add_schema("B", kClockSchema));
	assert_int_equal(a, 1);
	assert_int_equal(b, 2);
	assert_int_equal(MUST(w.add_schema("A", "jsonschema", kClockSchema)), a);
	assert_int_equal(MUST(w.add_channel("/x", a)), 0);
	assert_int_equal(MUST(w.add_channel("/x", a)), 1); // a second publisher on /x
	assert_int_equal(MUST(w.add_channel("/raw", "x-raw", 0)), 2);
	CHECK_OK(w.write(2, 1, 1, "raw"));
	CHECK_OK(w.close());
}

void expect_error(const tcs::Status &s, const std::string &part1, const std::string &part2)
{
	if (s.ok()) {
		print_error("succeeded; expected an error naming '%s' and '%s'\n", part1.c_str(), part2.c_str());
		fail();
	}
	const std::string &m = s.error().message;
	if (m.find(part1) == std::string::npos || m.find(part2) == std::string::npos) {
		print_error("error '%s' does not name '%s' and '%s'\n", m.c_str(), part1.c_str(), part2.c_str());
		fail();
	}
}

template <class T> tcs::Status status_of(const tcs::Result<T> &r)
{
	if (r.ok())
		return tcs::Ok{};
	return r.error();
}

void test_errors(void **)
{
	McapWriter w;
	expect_error(w.write(0, 0, 0, "x"), "no file is open", "");
	expect_error(status_of(w.add_schema("a", "b")), "no file is open", "");
	expect_error(w.open("/nonexistent-dir/t.mcap"), "/nonexistent-dir/t.mcap", "No such file");
	expect_error(w.open("/dev/full"), "/dev/full", "No space left on device");
	assert_false(w.is_open());

	std::string path = test_path("errors.mcap");
	CHECK_OK(w.open(path));
	expect_error(w.open(path), "still writing", path);
	expect_error(status_of(w.add_channel("/x", 3)), path, "no schema 3");
	expect_error(w.write(5, 0, 0, "{}"), path, "channel 5");
	uint16_t sc = MUST(w.add_schema("tcs.Clock", kClockSchema));
	uint16_t ch = MUST(w.add_channel("/clock", sc));
	CHECK_OK(w.write(ch, 1, 1, "{}"));
	CHECK_OK(w.close());
	CHECK_OK(w.close()); // closing twice is harmless
	expect_error(w.write(ch, 2, 2, "{}"), "no file is open", path);
	parse_ok(slurp(path), true);

	McapWriter bad_level(McapWriterOptions{ .zstd_level = 1000 });
	expect_error(bad_level.open(test_path("level.mcap")), "zstd level 1000", "");
}

// The file system refuses more bytes (a file size limit standing in for a
// full disk): the error names the file and the cause, sticks, and the file
// keeps the chunks written before.
void test_write_error(void **)
{
	struct rlimit old;
	assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
	struct sigaction ign = {}, old_sa;
	ign.sa_handler = SIG_IGN;
	assert_int_equal(sigaction(SIGXFSZ, &ign, &old_sa), 0);
	struct rlimit lim = { 100000, old.rlim_max };
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);

	std::string path = test_path("limited.mcap");
	McapWriter w(McapWriterOptions{ .chunk_size = 4096, .compression = McapCompression::none });
	tcs::Status opened = w.open(path);
	Sample s;
	tcs::Status st = tcs::Ok{};
	int i = 0;
	if (opened.ok()) {
		s.setup(w);
		for (; i < 100000 && st.ok(); i++) {
			st = w.write(s.ch[0], uint64_t(i), uint64_t(i), "{\"t_ns\":" + std::to_string(i) + "}");
			s.expected.push_back(Msg{ s.ch[0], uint32_t(i), uint64_t(i), uint64_t(i),
						  "{\"t_ns\":" + std::to_string(i) + "}" });
		}
	}
	tcs::Status again = w.write(s.ch[0], 0, 0, "{}");
	tcs::Status closed = w.close();
	setrlimit(RLIMIT_FSIZE, &old);
	sigaction(SIGXFSZ, &old_sa, nullptr);

	CHECK_OK(opened);
	expect_error(st, path, "File too large");
	expect_error(again, path, "File too large");
	expect_error(closed, path, "File too large");
	std::vector<uint8_t> f = slurp(path);
	assert_int_equal(f.size(), 100000);
	Parsed p = parse_ok(f, false);
	assert_true(p.chunks.size() > 10);
	expect_messages(p, s.expected, p.messages.size());
}

void test_destructor_closes(void **)
{
	std::string path = test_path("destructor.mcap");
	Sample s;
	{
		McapWriter w;
		CHECK_OK(w.open(path));
		s.setup(w);
		s.write(w, 0, 100);
	}
	expect_messages(parse_ok(slurp(path), true), s.expected, 100);
}

// A writing process killed with SIGKILL: its file reads up to the last
// chunk it wrote, every message in order.
void test_sigkill(void **)
{
	std::string path = test_path("sigkill.mcap");
	int pipefd[2];
	assert_int_equal(pipe2(pipefd, O_CLOEXEC), 0);
	pid_t parent = getpid();
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		// Never outlive the test, never fill the disk.
		prctl(PR_SET_PDEATHSIG, SIGKILL);
		if (getppid() != parent)
			_exit(1);
		::close(pipefd[0]);
		McapWriter w(McapWriterOptions{ .chunk_size = 16384 });
		if (!w.open(path).ok())
			_exit(2);
		Sample s;
		s.setup(w);
		for (int i = 0; w.file_bytes() < (256u << 20); i++) {
			Msg m = s.next(i);
			if (!w.write(m.channel, m.log, m.pub, m.data).ok())
				_exit(4);
			if (w.chunk_count() == 20 && pipefd[1] >= 0) {
				(void)!::write(pipefd[1], "x", 1);
				::close(pipefd[1]);
				pipefd[1] = -1;
			}
		}
		_exit(3);
	}
	::close(pipefd[1]);
	struct pollfd pfd = { pipefd[0], POLLIN, 0 };
	int ready = poll(&pfd, 1, 30000);
	char c = 0;
	ssize_t got = ready == 1 ? read(pipefd[0], &c, 1) : -1;
	kill(pid, SIGKILL);
	int status = 0;
	assert_int_equal(waitpid(pid, &status, 0), pid);
	::close(pipefd[0]);
	assert_int_equal(got, 1);
	assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);

	std::vector<uint8_t> f = slurp(path);
	Parsed p = parse_ok(f, false);
	assert_true(p.chunks.size() >= 20);
	// The child's messages 0, 1, ... on channels 0, 1, 2.
	Sample s = { .ch = { 0, 1, 2 } };
	for (size_t i = 0; i < p.messages.size(); i++)
		s.expected.push_back(s.next(int(i)));
	expect_messages(p, s.expected, p.messages.size());
	assert_int_equal(p.messages.size(), p.messages_after_chunk.back());
}

} // namespace

int main(void)
{
	if (const char *keep = getenv("TCS_MCAP_TEST_DIR"); keep && *keep) {
		g_dir = keep;
		g_keep = true;
		mkdir(keep, 0777);
	} else {
		char tmpl[] = "/tmp/tcs-mcap-test-XXXXXX";
		if (!mkdtemp(tmpl)) {
			perror("mkdtemp");
			return 1;
		}
		g_dir = tmpl;
	}
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_crc32),
		cmocka_unit_test(test_zstd_file),
		cmocka_unit_test(test_uncompressed_file),
		cmocka_unit_test(test_default_chunks),
		cmocka_unit_test(test_incompressible_chunks),
		cmocka_unit_test(test_out_of_order_times),
		cmocka_unit_test(test_truncated),
		cmocka_unit_test(test_flush),
		cmocka_unit_test(test_empty_files),
		cmocka_unit_test(test_large_message),
		cmocka_unit_test(test_schema_ids),
		cmocka_unit_test(test_errors),
		cmocka_unit_test(test_write_error),
		cmocka_unit_test(test_destructor_closes),
		cmocka_unit_test(test_sigkill),
	};
	int failed = cmocka_run_group_tests(tests, nullptr, nullptr);
	if (g_keep) {
		printf("# MCAP files kept in %s\n", g_dir.c_str());
	} else {
		for (const std::string &p : g_files)
			unlink(p.c_str());
		rmdir(g_dir.c_str());
	}
	return failed;
}
