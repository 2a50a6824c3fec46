// Unit tests for trace/mcap_reader on files the writer never makes:
// damaged ones (every byte flipped: an error naming the byte, or messages
// the file really had, never a crash) and hand-built ones (unchunked
// messages, unknown opcodes, lz4, lies about sizes, every malformed
// record), and a reader used again and copied.
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

#include "mcap_crc32.h"
#include "mcap_read_checks.h"
#include "mcap_reader.h"
#include "test_files.h"

namespace {

using namespace mcap_read_checks;
using namespace test_files;
using tcs::McapMessage;
using tcs::McapReader;

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
	if (!test_dir_open("tcs-mcap-reader-damage-test"))
		return 1;
	// One test alone, when debugging: TCS_TEST_test_flips_zstd=test_flips_zstd.
	if (getenv("TCS_TEST_test_flips_zstd"))
		cmocka_set_test_filter(getenv("TCS_TEST_test_flips_zstd"));
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_flips_zstd),
		cmocka_unit_test(test_flips_uncompressed),
		cmocka_unit_test(test_unchunked),
		cmocka_unit_test(test_malformed),
		cmocka_unit_test(test_reuse),
	};
	int failed = cmocka_run_group_tests(tests, nullptr, nullptr);
	test_dir_close();
	return failed;
}
