// Unit tests for trace/mcap_reader: files written by McapWriter read back
// message for message (zstd and uncompressed chunks), files cut at every
// length (the complete chunks, and truncated()), a file still being
// written, and files that are missing or not MCAP. Damaged and hand-built
// files are test_mcap_reader_damage.cc's.
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
#include "mcap_read_checks.h"
#include "mcap_reader.h"
#include "mcap_writer.h"
#include "test_files.h"

namespace {

using namespace mcap_read_checks;
using namespace test_files;
using tcs::McapMessage;
using tcs::McapReader;
using tcs::McapWriterOptions;

// ---- Files written by McapWriter ----

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

void test_missing_file(void **)
{
	McapReader r;
	tcs::Status s = r.open(test_dir() + "/no-such.mcap");
	assert_false(s.ok());
	assert_string_equal(s.error().message.c_str(), (test_dir() + "/no-such.mcap: No such file or directory").c_str());
	s = r.open(test_dir());
	assert_false(s.ok());
	assert_string_equal(s.error().message.c_str(), (test_dir() + ": Is a directory").c_str());
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

} // namespace

int main(void)
{
	if (!test_dir_open("tcs-mcap-reader-test"))
		return 1;
	// One test alone, when debugging: TCS_TEST_test_cut_zstd=test_cut_zstd.
	if (getenv("TCS_TEST_test_cut_zstd"))
		cmocka_set_test_filter(getenv("TCS_TEST_test_cut_zstd"));
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_zstd_file),
		cmocka_unit_test(test_uncompressed_file),
		cmocka_unit_test(test_cut_zstd),
		cmocka_unit_test(test_cut_uncompressed),
		cmocka_unit_test(test_open_file),
		cmocka_unit_test(test_missing_file),
		cmocka_unit_test(test_not_mcap),
	};
	int failed = cmocka_run_group_tests(tests, nullptr, nullptr);
	test_dir_close();
	return failed;
}
