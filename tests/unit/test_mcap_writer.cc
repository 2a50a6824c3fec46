// Unit tests for trace/mcap_writer: its CRC-32 (folded and by tables), and complete files read
// back (mcap_check.h: messages by the reader, and every record of their
// layout checked against the MCAP specification): chunks of each
// compression and size, incompressible data, log times out of order,
// flush(), empty files, messages larger than a chunk, schema and channel
// ids. Files cut short and writers stopped are test_mcap_writer_failures.cc's.
//
// The files go to a temporary directory that is removed afterwards, unless
// TCS_MCAP_TEST_DIR names a directory to keep them in (tests/mcap/check.mjs
// reads them with the reference TypeScript readers).
#include <algorithm>
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "result_checks.h"

#include "mcap_check.h"
#include "mcap_crc32.h"
#include "mcap_sample.h"
#include "mcap_writer.h"
#include "test_files.h"

namespace {

using namespace mcap_check;
using namespace test_files;
using tcs::McapCompression;
using tcs::McapWriter;
using tcs::McapWriterOptions;

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
	// Folded (64 bytes and more, where the CPU multiplies carry-less) and
	// by tables alone agree with the bit-by-bit reference, about each
	// multiple of 16 and 64, and carried on from a CRC so far.
	for (size_t len : { 63, 64, 65, 79, 80, 95, 127, 128, 129, 191, 192, 193, 255, 256, 1000, 4095, 4096, 8193 })
		for (size_t off = 0; off < 3; off++) {
			const uint8_t *p = data.data() + off;
			uint32_t want = ref_crc32(p, len);
			assert_int_equal(tcs::mcap_crc32(0, p, len), want);
			assert_int_equal(tcs::mcap_crc32_by_tables(0, p, len), want);
			for (size_t first : { size_t(1), size_t(17), len / 2 })
				assert_int_equal(tcs::mcap_crc32(tcs::mcap_crc32(0, p, first), p + first, len - first), want);
		}
	uint32_t whole = ref_crc32(data.data(), data.size());
	assert_int_equal(tcs::mcap_crc32(0, data.data(), data.size()), whole);
	assert_int_equal(tcs::mcap_crc32_by_tables(0, data.data(), data.size()), whole);
	// Two CRCs combined as the data section's is (a chunk's own CRC, not
	// read again), the first carried on from a CRC so far.
	for (size_t split : { size_t(0), size_t(1), size_t(4096), data.size() - 3, data.size() }) {
		uint32_t a = tcs::mcap_crc32(tcs::mcap_crc32(0, data.data(), 5), data.data() + 5, split - std::min(split, size_t(5)));
		uint32_t b = tcs::mcap_crc32(0, data.data() + std::max(split, size_t(5)), data.size() - std::max(split, size_t(5)));
		assert_int_equal(tcs::mcap_crc32_combine(a, b, data.size() - std::max(split, size_t(5))), whole);
	}
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

	std::string f = slurp(path);
	ReadBack p = read_back_ok(f, true);
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
	assert_string_equal(p.summary_channels[1].message_encoding.c_str(), "json");
	assert_string_equal(p.summary_channels[1].metadata.at("controller").c_str(), "pendulum_pd");
	assert_string_equal(p.summary_schemas[0].encoding.c_str(), "jsonschema");
	assert_int_equal(p.stats.message_count, 3000);
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
	ReadBack p = read_back_ok(slurp(path), true);
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
	ReadBack p = read_back_ok(slurp(path), true);
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
	ReadBack p = read_back_ok(slurp(path), true);
	expect_messages(p, want, want.size());
	assert_int_equal(p.stats.message_start_time, 10);
	assert_int_equal(p.stats.message_end_time, last);
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
	std::string f = slurp(path);
	assert_int_equal(f.size(), w.file_bytes());
	expect_messages(read_back_ok(f, false), s.expected, 5);
	s.write(w, 5, 10);
	CHECK_OK(w.close());
	ReadBack p = read_back_ok(slurp(path), true);
	expect_messages(p, s.expected, 10);
	assert_int_equal(p.chunks.size(), 2);
}

void test_empty_files(void **)
{
	std::string path = test_path("empty.mcap");
	McapWriter w;
	CHECK_OK(w.open(path));
	CHECK_OK(w.close());
	ReadBack p = read_back_ok(slurp(path), true);
	assert_int_equal(p.messages.size(), 0);
	assert_int_equal(p.chunks.size(), 0);
	assert_string_equal(p.library.c_str(), "tcs");

	// Reusing the writer for another file.
	path = test_path("no_messages.mcap");
	CHECK_OK(w.open(path));
	Sample s;
	s.setup(w);
	CHECK_OK(w.close());
	p = read_back_ok(slurp(path), true);
	assert_int_equal(p.messages.size(), 0);
	assert_int_equal(p.summary_channels.size(), 3);
	assert_int_equal(p.stats.channel_message_counts.size(), 3);
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
	ReadBack p = read_back_ok(slurp(path), true);
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

} // namespace

int main(void)
{
	if (!test_dir_open("tcs-mcap-writer-test", "TCS_MCAP_TEST_DIR"))
		return 1;
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_crc32),
		cmocka_unit_test(test_zstd_file),
		cmocka_unit_test(test_uncompressed_file),
		cmocka_unit_test(test_default_chunks),
		cmocka_unit_test(test_incompressible_chunks),
		cmocka_unit_test(test_out_of_order_times),
		cmocka_unit_test(test_flush),
		cmocka_unit_test(test_empty_files),
		cmocka_unit_test(test_large_message),
		cmocka_unit_test(test_schema_ids),
	};
	int failed = cmocka_run_group_tests(tests, nullptr, nullptr);
	test_dir_close();
	return failed;
}
