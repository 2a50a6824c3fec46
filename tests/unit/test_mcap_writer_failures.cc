// Unit tests for trace/mcap_writer when a file does not end as it should:
// cut anywhere (read from the start, it holds its complete chunks), a
// writer misused, stopped by a full file system, closed by its destructor,
// or SIGKILLed while writing. Files are read back as mcap_check.h does,
// and kept in TCS_MCAP_TEST_DIR when it names a directory.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "result_checks.h"

#include "mcap_check.h"
#include "mcap_sample.h"
#include "mcap_writer.h"
#include "test_files.h"

namespace {

using namespace mcap_check;
using namespace test_files;
using tcs::McapCompression;
using tcs::McapWriter;
using tcs::McapWriterOptions;

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
	std::string f = slurp(path);
	ReadBack whole = read_back_ok(f, true);
	assert_true(whole.chunks.size() > 6);

	// Messages in the first k chunks.
	auto upto = [&](size_t k) { return k ? whole.messages_after_chunk[k - 1] : 0; };
	auto cut = [&](size_t at) { return read_back_ok(f.substr(0, at), false); };

	const ChunkInfo &c3 = whole.chunks[3];
	// In the middle of chunk 3's record: chunks 0-2.
	ReadBack p = cut(c3.offset + c3.length / 2);
	assert_int_equal(p.chunks.size(), 3);
	expect_messages(p, s.expected, upto(3));
	spit(test_path("truncated.mcap"), std::string_view(f).substr(0, c3.offset + c3.length / 2));
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
	// Cut inside the magic: to the reader, no MCAP file at all.
	for (size_t at = 0; at < 8; at++)
		assert_string_equal(read_back(f.substr(0, at)).error.c_str(), "file: not an MCAP file");
	// All chunks, cut in the summary or the footer.
	expect_messages(cut(f.size() - 40), s.expected, s.expected.size());
	expect_messages(cut(f.size() - 1), s.expected, s.expected.size());
	// Every cut point in the first chunks.
	for (size_t at = 8; at < whole.chunks[2].offset; at += 37)
		(void)cut(at);
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
	read_back_ok(slurp(path), true);

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
	std::string f = slurp(path);
	assert_int_equal(f.size(), 100000);
	ReadBack p = read_back_ok(f, false);
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
	expect_messages(read_back_ok(slurp(path), true), s.expected, 100);
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

	std::string f = slurp(path);
	ReadBack p = read_back_ok(f, false);
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
	if (!test_dir_open("tcs-mcap-writer-failures-test", "TCS_MCAP_TEST_DIR"))
		return 1;
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_truncated),
		cmocka_unit_test(test_errors),
		cmocka_unit_test(test_write_error),
		cmocka_unit_test(test_destructor_closes),
		cmocka_unit_test(test_sigkill),
	};
	int failed = cmocka_run_group_tests(tests, nullptr, nullptr);
	test_dir_close();
	return failed;
}
