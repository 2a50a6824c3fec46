// Unit tests for trace/mcap_reader: files written by McapWriter read
// back message for message (zstd and uncompressed chunks), files cut at
// every length (the complete chunks, and truncated()), damaged files (an
// error naming the byte, never a crash), hand-built files for what the
// writer never produces (unchunked messages, unknown opcodes, lz4, lies
// about sizes).
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "result_checks.h"

#include "json.h"
#include "mcap_reader.h"
#include "mcap_crc32.h"
#include "mcap_writer.h"

namespace {

using tcs::McapCompression;
using tcs::McapMessage;
using tcs::McapReader;
using tcs::McapWriter;
using tcs::McapWriterOptions;

std::string g_dir;
std::vector<std::string> g_files;

std::string test_path(const std::string &name)
{
	std::string p = g_dir + "/" + name;
	g_files.push_back(p);
	return p;
}

std::string slurp(const std::string &path)
{
	std::string out;
	FILE *f = std::fopen(path.c_str(), "rb");
	assert_non_null(f);
	char buf[65536];
	size_t n;
	while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
		out.append(buf, n);
	std::fclose(f);
	return out;
}

void spit(const std::string &path, const std::string &bytes)
{
	FILE *f = std::fopen(path.c_str(), "wb");
	assert_non_null(f);
	assert_int_equal(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
	assert_int_equal(std::fclose(f), 0);
}


// A message as the reader returned it, or as the test wrote it.
struct Msg {
	uint16_t channel = 0;
	std::string topic, schema; // schema: its name, "" for none
	uint32_t seq = 0;
	uint64_t log = 0, pub = 0;
	std::string data;
	bool operator==(const Msg &) const = default;
};

// Everything one reader says about a file.
struct Outcome {
	bool opened = false;
	std::string error; // open's or next()'s, or ""
	std::vector<Msg> messages;
	bool truncated = false;
	uint64_t unread = 0;
};

Outcome read_bytes(const std::string &name, std::string bytes)
{
	Outcome o;
	McapReader r;
	tcs::Status s = r.open_bytes(name, std::move(bytes));
	if (!s) {
		o.error = s.error().message;
		return o;
	}
	o.opened = true;
	for (;;) {
		McapMessage m;
		auto more = r.next(&m);
		if (!more) {
			o.error = more.error().message;
			// The error sticks.
			auto again = r.next(&m);
			assert_false(again.ok());
			assert_string_equal(again.error().message.c_str(), o.error.c_str());
			return o;
		}
		if (!*more)
			break;
		assert_non_null(m.channel);
		assert_true(m.channel->schema_id == 0 ? m.schema == nullptr : m.schema && m.schema->id == m.channel->schema_id);
		o.messages.push_back(Msg{ m.channel->id, m.channel->topic, m.schema ? m.schema->name : "", m.sequence,
					  m.log_time, m.publish_time, std::string(m.data) });
	}
	o.truncated = r.truncated();
	o.unread = r.bytes_unread();
	McapMessage m;
	auto after = r.next(&m); // the end stays the end
	assert_true(after.ok() && !*after);
	return o;
}

void expect_error(const Outcome &o, const std::string &part1, const std::string &part2 = "")
{
	if (o.error.empty() || o.error.find(part1) == std::string::npos || o.error.find(part2) == std::string::npos) {
		print_error("got error '%s' after %zu messages; expected one naming '%s' and '%s'\n", o.error.c_str(),
			    o.messages.size(), part1.c_str(), part2.c_str());
		fail();
	}
}

void expect_complete(const Outcome &o, size_t messages)
{
	if (!o.error.empty() || o.truncated || o.messages.size() != messages) {
		print_error("error '%s', truncated %d, %zu messages; expected a complete file of %zu\n", o.error.c_str(),
			    o.truncated, o.messages.size(), messages);
		fail();
	}
}

// ---- Files written by McapWriter ----

const char kClockSchema[] = R"({"type":"object","properties":{"t_ns":{"type":"integer"}}})";
const char kSliceSchema[] = R"({"type":"object","properties":{"controller":{"type":"string"}}})";

// Four channels, one without a schema; deterministic JSON messages. Also
// what the writer says after each chunk: how many messages the chunks so
// far hold.
struct Sample {
	std::vector<Msg> expected;
	std::vector<size_t> messages_after_chunk;

	void write(McapWriter &w, int count)
	{
		uint16_t clock = MUST(w.add_schema("tcs.Clock", kClockSchema));
		uint16_t slice = MUST(w.add_schema("tcs.Slice", kSliceSchema));
		struct {
			uint16_t id;
			const char *topic, *schema;
			uint32_t seq;
		} ch[4] = {
			{ MUST(w.add_channel("/clock", clock)), "/clock", "tcs.Clock", 0 },
			{ MUST(w.add_channel("/tcs/slices/a", slice)), "/tcs/slices/a", "tcs.Slice", 0 },
			{ MUST(w.add_channel("/tcs/slices/b", slice, { { "controller", "b" } })), "/tcs/slices/b", "tcs.Slice", 0 },
			{ MUST(w.add_channel("/raw", 0)), "/raw", "", 0 },
		};
		for (int i = 0; i < count; i++) {
			auto &c = ch[(i * 7) % 11 % 4];
			uint64_t t = 1'000'000 + 997 * uint64_t(i);
			std::string json = "{\"t_ns\":" + std::to_string(t) + ",\"controller\":\"c" + std::to_string(i % 3) +
					   std::string(i % 17, 'x') + "\",\"big\":9007199254740993,\"f\":-1.5e-3}";
			uint32_t chunks = w.chunk_count();
			CHECK_OK(w.write(c.id, t, t + 3, json));
			expected.push_back(Msg{ c.id, c.topic, c.schema, c.seq++, t, t + 3, json });
			if (w.chunk_count() != chunks)
				messages_after_chunk.push_back(expected.size());
		}
	}
};

std::string write_sample(const char *name, McapCompression compression, size_t chunk_size, int count, Sample &s)
{
	std::string path = test_path(name);
	McapWriter w(McapWriterOptions{ .chunk_size = chunk_size, .compression = compression });
	CHECK_OK(w.open(path, "x-tcs", "tcs test"));
	s.write(w, count);
	uint32_t chunks = w.chunk_count();
	CHECK_OK(w.close());
	if (w.chunk_count() != chunks)
		s.messages_after_chunk.push_back(s.expected.size());
	return path;
}

// The top-level records of a file, found independently of the reader: where
// each ends, and where its Chunk records end.
struct Layout {
	std::vector<size_t> record_ends, chunk_ends;
	std::vector<size_t> chunk_starts;
};

Layout layout(const std::string &f)
{
	Layout l;
	size_t pos = 8;
	while (f.size() - pos >= 9) {
		uint64_t len = 0;
		for (int i = 0; i < 8; i++)
			len |= uint64_t(uint8_t(f[pos + 1 + i])) << (8 * i);
		if (len > f.size() - pos - 9)
			break;
		uint8_t op = uint8_t(f[pos]);
		if (op == 0x06)
			l.chunk_starts.push_back(pos);
		pos += 9 + len;
		l.record_ends.push_back(pos);
		if (op == 0x06)
			l.chunk_ends.push_back(pos);
		if (op == 0x02)
			break;
	}
	return l;
}

void check_written(McapCompression compression, const char *name)
{
	Sample s;
	std::string path = write_sample(name, compression, 1024, 2000, s);
	McapReader r;
	CHECK_OK(r.open(path));
	assert_string_equal(r.profile().c_str(), "x-tcs");
	assert_string_equal(r.library().c_str(), "tcs test");
	assert_string_equal(r.name().c_str(), path.c_str());
	Outcome o = read_bytes(path, slurp(path));
	expect_complete(o, s.expected.size());
	for (size_t i = 0; i < o.messages.size(); i++)
		if (!(o.messages[i] == s.expected[i])) {
			print_error("message %zu differs: %s\n", i, o.messages[i].data.c_str());
			fail();
		}
	assert_true(s.messages_after_chunk.size() > 20);
	assert_int_equal(layout(slurp(path)).chunk_ends.size(), s.messages_after_chunk.size());
	// The reader's definitions are the writer's.
	while (true) {
		McapMessage m;
		auto more = r.next(&m);
		assert_true(more.ok());
		if (!*more)
			break;
	}
	assert_int_equal(r.channels().size(), 4);
	assert_int_equal(r.schemas().size(), 2);
	assert_string_equal(r.schemas().at(1).data.c_str(), kClockSchema);
	assert_string_equal(r.schemas().at(1).encoding.c_str(), "jsonschema");
	assert_string_equal(r.channels().at(3).message_encoding.c_str(), "json");
	assert_false(r.truncated());
	// And every message is JSON with its 53-bit-plus integer exact.
	for (const Msg &m : o.messages) {
		tcs::JsonValue v = MUST(tcs::json_parse(m.data));
		assert_int_equal(v.get_int("t_ns"), m.log);
		assert_true(v.get_int("big") == 9007199254740993);
	}
}

void test_zstd_file(void **) { check_written(McapCompression::zstd, "zstd.mcap"); }
void test_uncompressed_file(void **) { check_written(McapCompression::none, "none.mcap"); }

// A file cut at every length reads as its complete chunks, truncated, with
// the bytes past the last complete record unread; never an error.
void check_cuts(McapCompression compression, const char *name)
{
	Sample s;
	std::string f = slurp(write_sample(name, compression, 512, 150, s));
	Layout l = layout(f);
	assert_int_equal(l.chunk_ends.size(), s.messages_after_chunk.size());
	assert_true(l.chunk_ends.size() > 10);
	assert_int_equal(l.record_ends.back() + 8, f.size());
	size_t chunks = 0, records = 0;
	for (size_t at = 0; at <= f.size(); at++) {
		Outcome o = read_bytes("cut", f.substr(0, at));
		if (at < 8) {
			expect_error(o, "cut: not an MCAP file");
			continue;
		}
		while (chunks < l.chunk_ends.size() && l.chunk_ends[chunks] <= at)
			chunks++;
		while (records < l.record_ends.size() && l.record_ends[records] <= at)
			records++;
		size_t want = chunks ? s.messages_after_chunk[chunks - 1] : 0;
		size_t complete_to = records ? l.record_ends[records - 1] : 8;
		if (!o.error.empty() || o.messages.size() != want || o.truncated != (at < f.size()) ||
		    o.unread != at - (at < f.size() ? complete_to : at)) {
			print_error("cut at %zu of %zu: error '%s', %zu messages (want %zu), truncated %d, %lu unread "
				    "(want %zu)\n",
				    at, f.size(), o.error.c_str(), o.messages.size(), want, o.truncated,
				    (unsigned long)o.unread, at - complete_to);
			fail();
		}
		for (size_t i = 0; i < o.messages.size(); i++)
			assert_true(o.messages[i] == s.expected[i]);
	}
}

void test_cut_zstd(void **) { check_cuts(McapCompression::zstd, "cut_zstd.mcap"); }
void test_cut_uncompressed(void **) { check_cuts(McapCompression::none, "cut_none.mcap"); }

// A file still being written: its flushed chunks, and no footer.
void test_open_file(void **)
{
	std::string path = test_path("open.mcap");
	McapWriter w;
	CHECK_OK(w.open(path));
	uint16_t ch = MUST(w.add_channel("/x", 0));
	CHECK_OK(w.write(ch, 5, 5, "{}"));
	CHECK_OK(w.flush());
	McapReader r;
	CHECK_OK(r.open(path));
	McapMessage m;
	assert_true(MUST(r.next(&m)));
	assert_string_equal(m.channel->topic.c_str(), "/x");
	assert_null(m.schema);
	assert_false(MUST(r.next(&m)));
	assert_true(r.truncated());
	assert_int_equal(r.bytes_unread(), 0);
	CHECK_OK(w.close());
}

// ---- Damage ----

// Whatever a damaged file holds, the reader returns messages the file
// really had, in order, then either an error naming the byte or an end.
void expect_sane(const Outcome &o, const std::vector<Msg> &all, size_t flipped)
{
	if (!o.error.empty() && o.error.rfind("flip: at byte ", 0) != 0 &&
	    (flipped >= 8 || o.error != "flip: not an MCAP file")) {
		print_error("flip at %zu: error '%s' does not name the byte\n", flipped, o.error.c_str());
		fail();
	}
	size_t j = 0;
	for (const Msg &m : o.messages) {
		while (j < all.size() && !(all[j] == m))
			j++;
		if (j == all.size()) {
			print_error("flip at %zu: a message the file never had: %s\n", flipped, m.data.c_str());
			fail();
		}
		j++;
	}
}

void check_flips(McapCompression compression, const char *name)
{
	Sample s;
	std::string f = slurp(write_sample(name, compression, 512, 120, s));
	Layout l = layout(f);
	size_t errors = 0, in_data = 0, harmless = 0;
	for (size_t at = 0; at < f.size(); at++) {
		std::string g = f;
		g[at] = char(g[at] ^ 0x5A);
		Outcome o = read_bytes("flip", g);
		expect_sane(o, s.expected, at);
		errors += !o.error.empty();
		// In a chunk's stored records (past its 9-byte head, four
		// u64s, a CRC and the compression string): a CRC or zstd
		// error, or at worst an end cut short.
		for (size_t k = 0; k < l.chunk_starts.size(); k++) {
			const size_t compression_at = l.chunk_starts[k] + 9 + 8 * 3 + 4;
			const size_t records = compression_at + 4 + uint8_t(f[compression_at]) + 8;
			if (at >= records && at < l.chunk_ends[k]) {
				in_data++;
				// zstd data has bits that change nothing (without a
				// frame checksum): then the records, which the CRC
				// covers, must have come out the same.
				if (o.error.empty() && !o.truncated) {
					if (compression == McapCompression::none || o.messages != s.expected) {
						print_error("flip at %zu, in chunk %zu's records, went unnoticed\n", at, k);
						fail();
					}
					harmless++;
				}
				if (compression == McapCompression::none)
					expect_error(o, "CRC");
			}
		}
	}
	assert_true(in_data > 1000);
	assert_true(harmless < in_data / 100);
	assert_true(errors > in_data);
}

void test_flips_zstd(void **) { check_flips(McapCompression::zstd, "flip_zstd.mcap"); }
void test_flips_uncompressed(void **) { check_flips(McapCompression::none, "flip_none.mcap"); }

void test_missing_file(void **)
{
	McapReader r;
	tcs::Status s = r.open(g_dir + "/no-such.mcap");
	assert_false(s.ok());
	assert_string_equal(s.error().message.c_str(), (g_dir + "/no-such.mcap: No such file or directory").c_str());
	s = r.open(g_dir);
	assert_false(s.ok());
	assert_string_equal(s.error().message.c_str(), (g_dir + ": Is a directory").c_str());
}

void test_not_mcap(void **)
{
	const std::string texts[] = { "", "\x89MCA", "hello, world\n", "\x89MCAP1\r\n", std::string(100, '\0') };
	for (const std::string &t : texts) {
		std::string path = test_path("not.mcap");
		spit(path, t);
		McapReader r;
		tcs::Status s = r.open(path);
		assert_false(s.ok());
		assert_string_equal(s.error().message.c_str(), (path + ": not an MCAP file").c_str());
	}
}

// ---- Hand-built files ----

struct Bytes {
	std::string b;
	Bytes &le(uint64_t v, int k)
	{
		for (int i = 0; i < k; i++)
			b += char(v >> (8 * i));
		return *this;
	}
	Bytes &u8(uint8_t v) { return le(v, 1); }
	Bytes &u16(uint16_t v) { return le(v, 2); }
	Bytes &u32(uint32_t v) { return le(v, 4); }
	Bytes &u64(uint64_t v) { return le(v, 8); }
	Bytes &str(const std::string &s) { return u32(uint32_t(s.size())).raw(s); }
	Bytes &raw(const std::string &s)
	{
		b += s;
		return *this;
	}
};

const std::string kMagic("\x89MCAP0\r\n", 8);

std::string record(uint8_t op, const std::string &body) { return Bytes().u8(op).u64(body.size()).raw(body).b; }
std::string header() { return record(0x01, Bytes().str("p").str("lib").b); }
std::string schema(uint16_t id, const std::string &name)
{
	return record(0x03, Bytes().u16(id).str(name).str("jsonschema").str("{}").b);
}
std::string channel(uint16_t id, uint16_t schema_id, const std::string &topic)
{
	return record(0x04, Bytes().u16(id).u16(schema_id).str(topic).str("json").u32(0).b);
}
std::string message(uint16_t ch, uint64_t t, const std::string &data)
{
	return record(0x05, Bytes().u16(ch).u32(0).u64(t).u64(t).raw(data).b);
}

// A Chunk of records; size and crc override the true ones when not ~0.
std::string chunk(const std::string &records, const std::string &compression, uint64_t size = ~0ull,
		  uint32_t crc = ~0u)
{
	std::string stored = records;
	if (compression == "zstd") {
		stored.resize(ZSTD_compressBound(records.size()));
		size_t n = ZSTD_compress(stored.data(), stored.size(), records.data(), records.size(), 3);
		assert_false(ZSTD_isError(n));
		stored.resize(n);
	}
	return record(0x06, Bytes()
				    .u64(0)
				    .u64(0)
				    .u64(size != ~0ull ? size : records.size())
				    .u32(crc != ~0u ? crc : tcs::mcap_crc32(0, records.data(), records.size()))
				    .str(compression)
				    .u64(stored.size())
				    .raw(stored)
				    .b);
}

std::string footer() { return record(0x0F, Bytes().u32(0).b) + record(0x02, Bytes().u64(0).u64(0).u32(0).b) + kMagic; }
std::string file(const std::string &records, bool closed = true)
{
	return kMagic + header() + records + (closed ? footer() : "");
}

const std::string kDefs = schema(1, "S") + channel(0, 1, "/a") + channel(7, 0, "/b");

void test_unchunked(void **)
{
	// Messages outside chunks, unknown opcodes and repeated definitions
	// at the top level and in a chunk.
	std::string f = file(kDefs + message(0, 1, "{\"a\":1}") + record(0x80, "future") + kDefs +
			     record(0x0D, "index") + message(7, 2, "[]") +
			     chunk(kDefs + record(0x99, "") + message(7, 3, "3"), "") +
			     chunk(message(0, 4, "4") + record(0x07, "x"), "zstd") +
			     chunk(message(0, 5, "5"), "", ~0ull, 0 /* not computed */));
	Outcome o = read_bytes("hand", f);
	expect_complete(o, 5);
	assert_string_equal(o.messages[1].topic.c_str(), "/b");
	assert_string_equal(o.messages[1].schema.c_str(), "");
	assert_string_equal(o.messages[3].schema.c_str(), "S");
	for (uint64_t i = 0; i < 5; i++)
		assert_int_equal(o.messages[i].log, i + 1);
	McapReader r;
	CHECK_OK(r.open_bytes("hand", f));
	assert_string_equal(r.profile().c_str(), "p");
	assert_string_equal(r.library().c_str(), "lib");

	// Cut: the record cut short is unread, from its first byte.
	const size_t whole = kMagic.size() + header().size() + kDefs.size();
	o = read_bytes("hand", file(kDefs + message(0, 1, "{}"), false).substr(0, whole + 20));
	assert_true(o.error.empty() && o.truncated && o.messages.empty());
	assert_int_equal(o.unread, 20);
	// Footer without its closing magic, or only part of it.
	std::string closed = file(kDefs + message(0, 1, "{}"));
	o = read_bytes("hand", closed.substr(0, closed.size() - 3));
	assert_true(o.error.empty() && o.truncated && o.messages.size() == 1);
	assert_int_equal(o.unread, 5);
	expect_error(read_bytes("hand", closed + "junk"), "hand: at byte " + std::to_string(closed.size()), "after the closing magic");
	expect_error(read_bytes("hand", closed.substr(0, closed.size() - 1) + "X"), "not followed by the closing magic");
}

// Each damage is an error at the byte of the record concerned.
void test_malformed(void **)
{
	const size_t at = kMagic.size() + header().size(); // the first record
	auto expect = [&](const std::string &records, const std::string &what, size_t where) {
		expect_error(read_bytes("bad", file(records)), "bad: at byte " + std::to_string(where) + ": ", what);
	};
	expect(message(3, 1, "{}"), "channel 3, which no Channel record defined", at);
	expect(kDefs + channel(0, 1, "/other"), "Channel 0 redefined differently", at + kDefs.size());
	expect(kDefs + record(0x03, Bytes().u16(1).str("S").str("jsonschema").str("{ }").b), "Schema 1 redefined", at + kDefs.size());
	expect(schema(0, "S"), "id 0", at);
	expect(channel(2, 9, "/a"), "Schema 9", at);
	expect(record(0x05, "short"), "shorter than its fixed fields", at);
	expect(record(0x03, Bytes().u16(1).u32(1000).b), "run past", at);
	expect(record(0x04, Bytes().u16(1).u16(0).str("/t").str("json").u32(5).raw(std::string("\x02\0\0\0a", 5)).b), "metadata", at);
	expect(header(), "a second Header", at);
	// In chunks: the error names the chunk's byte and the record's offset.
	expect(chunk(kDefs + message(9, 1, "{}"), ""), "offset " + std::to_string(kDefs.size()) + ": a Message on channel 9", at);
	expect(chunk(kDefs + "\x05\xff", ""), "cut short by the end of the Chunk", at);
	expect(chunk(kDefs + Bytes().u8(5).u64(1 << 20).b, ""), "runs past the end of the Chunk", at);
	expect(chunk(header(), ""), "which a Chunk cannot hold", at);
	expect(chunk(kDefs, "", ~0ull, 12345), "CRC", at);
	expect(chunk(kDefs, "", kDefs.size() + 1), "declares", at);
	expect(chunk(kDefs, "lz4"), "lz4 chunks are not supported", at);
	expect(chunk(kDefs, "brotli"), "compression 'brotli' is unknown", at);
	expect(record(0x06, Bytes().u64(0).u64(0).u64(10).u32(0).str("").u64(1000).raw("0123456789").b), "run past", at);
	// zstd chunks lying about their size are refused before allocating.
	expect(chunk(kDefs, "zstd", uint64_t(3) << 30), "more than the 1 GiB", at);
	expect(chunk(kDefs, "zstd", 100 << 20), "bytes of zstd data can hold", at);
	expect(chunk(kDefs, "zstd", kDefs.size() + 1), "zstd frame holds", at);
	expect(chunk(kDefs, "zstd", kDefs.size() - 1), "zstd frame holds", at);
	std::string z = chunk(kDefs, "zstd");
	z[z.size() - 3] ^= 0x55;
	expect(z, "", at);
	expect(chunk("garbage!", "zstd"), "", at);
	expect(record(0x06, Bytes().u64(0).u64(0).u64(8).u32(0).str("zstd").u64(8).raw("garbage!").b), "not a zstd frame", at);
	// Not a Header first.
	McapReader r;
	tcs::Status s = r.open_bytes("bad", kMagic + kDefs);
	assert_false(s.ok());
	assert_string_equal(s.error().message.c_str(), "bad: at byte 8: the first record has opcode 3, not a Header's");
	s = r.open_bytes("bad", kMagic + record(0x01, "\xff\xff"));
	assert_false(s.ok());
}

// A reader can be used again, and copied.
void test_reuse(void **)
{
	McapReader r;
	CHECK_OK(r.open_bytes("one", file(kDefs + chunk(message(0, 1, "1") + message(0, 2, "2"), ""))));
	McapMessage m;
	assert_true(MUST(r.next(&m)));
	McapReader copy = r;
	assert_true(MUST(copy.next(&m)));
	assert_string_equal(std::string(m.data).c_str(), "2");
	assert_false(MUST(copy.next(&m)));
	CHECK_OK(r.open_bytes("two", file(message(0, 1, "x"))));
	assert_true(r.channels().empty());
	auto e = r.next(&m);
	assert_false(e.ok());
	std::string want = "two: at byte " + std::to_string(kMagic.size() + header().size()) +
			   ": a Message on channel 0, which no Channel record defined before it";
	assert_string_equal(e.error().message.c_str(), want.c_str());
}

} // namespace

int main(void)
{
	char tmpl[] = "/tmp/tcs-mcap-reader-test-XXXXXX";
	if (!mkdtemp(tmpl)) {
		perror("mkdtemp");
		return 1;
	}
	g_dir = tmpl;
	// One test alone, when debugging: TCS_TEST_FILTER=test_cut_zstd.
	if (getenv("TCS_TEST_FILTER"))
		cmocka_set_test_filter(getenv("TCS_TEST_FILTER"));
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_zstd_file),
		cmocka_unit_test(test_uncompressed_file),
		cmocka_unit_test(test_cut_zstd),
		cmocka_unit_test(test_cut_uncompressed),
		cmocka_unit_test(test_open_file),
		cmocka_unit_test(test_flips_zstd),
		cmocka_unit_test(test_flips_uncompressed),
		cmocka_unit_test(test_missing_file),
		cmocka_unit_test(test_not_mcap),
		cmocka_unit_test(test_unchunked),
		cmocka_unit_test(test_malformed),
		cmocka_unit_test(test_reuse),
	};
	int failed = cmocka_run_group_tests(tests, nullptr, nullptr);
	for (const std::string &p : g_files)
		unlink(p.c_str());
	rmdir(g_dir.c_str());
	return failed;
}
