// Unit tests for coordinatord's attach protocol
// (coordinator/attach_protocol.h): every frame encoded and decoded back,
// each thing a decoder refuses and why, frames taken off a stream only
// when whole. Inputs found by tests/fuzz/attach_fuzz are kept here. The
// socket is test_attach_socket.cc's.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "attach_checks.h"
#include "attach_protocol.h"
#include "result_checks.h"

using namespace tcs;

namespace {

using namespace attach_checks;

// A header as anyone may write it, in the host's byte order.
std::string header(uint32_t magic, uint16_t version, uint16_t type, uint32_t length)
{
	std::string h(kAttachHeader, '\0');
	memcpy(&h[0], &magic, 4);
	memcpy(&h[4], &version, 2);
	memcpy(&h[6], &type, 2);
	memcpy(&h[8], &length, 4);
	return h;
}

std::string u32(uint32_t v)
{
	return std::string(reinterpret_cast<const char *>(&v), sizeof v);
}

std::string f64(double v)
{
	return std::string(reinterpret_cast<const char *>(&v), sizeof v);
}

// take_frame's error for a buffer, which it must leave as it was.
std::string frame_error(const std::string &bytes)
{
	std::string buf = bytes;
	auto f = take_frame(buf);
	assert_false(f.ok());
	assert_true(buf == bytes);
	return f.error().message;
}

// decode_run's refusal of a request edited from the typical one.
std::string run_refusal(void (*edit)(RunRequest &))
{
	RunRequest r = typical_run();
	edit(r);
	auto d = decode_run(encode_run(r));
	assert_false(d.ok());
	return d.error().message;
}

// ---- Frames ----

void round_trip_frames(void **)
{
	StartedReply s;
	s.id = 3;
	s.pid = 4242;
	s.mode = 1;
	s.fifo_cpu = -1;
	s.v_start = INT64_MAX;
	EndedReply e;
	e.wait_status = 0x8b; // killed by SIGSEGV, core dumped
	e.flags = kEndedByTcs | kEndedAttached;
	e.v_end = -5;
	e.charged_ns = 63778000;
	e.waits = UINT64_MAX;
	e.periodic_waits = 10001;
	e.deadline_misses = 2;
	e.preemptions = 5;
	e.dropped = "it sent a malformed message";

	std::string stream = encode_frame(AttachType::Run, encode_run(typical_run())) +
			     encode_frame(AttachType::Signal, encode_signal(64)) +
			     encode_frame(AttachType::Started, encode_started(s)) +
			     encode_frame(AttachType::Refused, "no: not today") +
			     encode_frame(AttachType::Ended, encode_ended(e));

	auto f = MUST(take_frame(stream));
	assert_true(f && f->type == AttachType::Run);
	assert_same_run(MUST(decode_run(f->payload)), typical_run());

	f = MUST(take_frame(stream));
	assert_true(f && f->type == AttachType::Signal);
	assert_int_equal(MUST(decode_signal(f->payload)), 64);

	f = MUST(take_frame(stream));
	assert_true(f && f->type == AttachType::Started);
	StartedReply s2 = MUST(decode_started(f->payload));
	assert_int_equal(s2.id, 3);
	assert_int_equal(s2.pid, 4242);
	assert_int_equal(s2.mode, 1);
	assert_int_equal(s2.fifo_cpu, -1);
	assert_true(s2.v_start == INT64_MAX);

	f = MUST(take_frame(stream));
	assert_true(f && f->type == AttachType::Refused);
	assert_string_equal(f->payload.c_str(), "no: not today");

	f = MUST(take_frame(stream));
	assert_true(f && f->type == AttachType::Ended);
	EndedReply e2 = MUST(decode_ended(f->payload));
	assert_int_equal(e2.wait_status, 0x8b);
	assert_int_equal(e2.flags, kEndedByTcs | kEndedAttached);
	assert_true(e2.v_end == -5 && e2.charged_ns == 63778000);
	assert_true(e2.waits == UINT64_MAX && e2.periodic_waits == 10001);
	assert_true(e2.deadline_misses == 2 && e2.preemptions == 5);
	assert_string_equal(e2.dropped.c_str(), "it sent a malformed message");

	assert_true(stream.empty());
	assert_false(MUST(take_frame(stream)).has_value());

	// An ended reply with nothing dropped, and empty payloads.
	EndedReply plain;
	EndedReply plain2 = MUST(decode_ended(encode_ended(plain)));
	assert_int_equal(plain2.wait_status, -1);
	assert_true(plain2.dropped.empty());
	std::string empty = encode_frame(AttachType::Refused, "");
	assert_int_equal(empty.size(), kAttachHeader);
	f = MUST(take_frame(empty));
	assert_true(f && f->payload.empty() && empty.empty());
}

// A CPU scale of 0 (the daemon's choice) and the smallest positive one
// travel exactly.
void run_cpu_scales(void **)
{
	for (double scale : { 0.0, 5e-324, 1.0, 1e6 }) {
		RunRequest r = typical_run();
		r.cpu_scale = scale;
		assert_same_run(MUST(decode_run(encode_run(r))), r);
	}
}

// A login shell's environment, and more: 200 KiB in one frame.
void run_large_environment(void **)
{
	RunRequest r = typical_run();
	size_t bytes = 0;
	for (int i = 0; bytes < 200 * 1024; i++) {
		r.env.push_back("VAR_" + std::to_string(i) + "=" + std::string(200, char('a' + i % 26)));
		bytes += r.env.back().size();
	}
	std::string stream = encode_frame(AttachType::Run, encode_run(r));
	assert_true(stream.size() > 200 * 1024 && stream.size() < kAttachMaxFrame);
	// As a socket delivers it: nothing until the last byte is there.
	std::string buf;
	for (size_t at = 0; at < stream.size(); at += 16384) {
		assert_false(MUST(take_frame(buf)).has_value());
		buf.append(stream, at, 16384);
	}
	auto f = MUST(take_frame(buf));
	assert_true(f && buf.empty());
	assert_same_run(MUST(decode_run(f->payload)), r);
}

// A frame and a half: the whole one is taken, exactly the half stays.
void one_and_a_half_frames(void **)
{
	const std::string first = encode_frame(AttachType::Run, encode_run(typical_run()));
	const std::string second = encode_frame(AttachType::Signal, encode_signal(2));
	const std::string half = second.substr(0, second.size() / 2 + 3); // past the header
	std::string buf = first + half;
	auto f = MUST(take_frame(buf));
	assert_true(f && f->type == AttachType::Run);
	assert_true(buf == half);
	assert_false(MUST(take_frame(buf)).has_value());
	assert_true(buf == half);
	buf += second.substr(half.size());
	f = MUST(take_frame(buf));
	assert_true(f && f->type == AttachType::Signal && buf.empty());
	// A header alone, cut short, waits too.
	buf = first.substr(0, kAttachHeader - 1);
	assert_false(MUST(take_frame(buf)).has_value());
	assert_int_equal(buf.size(), kAttachHeader - 1);
}

// ---- Refusals ----

void refused_headers(void **)
{
	const std::string payload = encode_signal(2);
	const std::string foreign = header(0x50545448, kAttachVersion, 2, 4) + payload;
	assert_true(contains(frame_error(foreign), "not a tcs attach request"));
	assert_true(contains(frame_error("GET / HTTP/1.1\r\nHost: x\r\n\r\n"), "not a tcs attach request"));

	// Another version names both, and what differs.
	std::string why = frame_error(header(kAttachMagic, 2, 2, 4) + payload);
	assert_true(contains(why, "version 2"));
	assert_true(contains(why, "version 1"));
	assert_true(contains(why, "tcs-run and coordinatord differ"));
	why = frame_error(header(kAttachMagic, 0, 2, 4) + payload);
	assert_true(contains(why, "version 0"));

	assert_true(contains(frame_error(header(kAttachMagic, kAttachVersion, 0, 0)), "unknown attach frame type 0"));
	assert_true(contains(frame_error(header(kAttachMagic, kAttachVersion, 6, 0)), "unknown attach frame type 6"));

	// Oversized: refused from the header, before anything more arrives.
	why = frame_error(header(kAttachMagic, kAttachVersion, 1, kAttachMaxFrame + 1));
	assert_true(contains(why, "1048577 bytes"));
	assert_true(contains(why, "the limit is 1048576"));
	assert_true(contains(frame_error(header(kAttachMagic, kAttachVersion, 1, UINT32_MAX)), "4294967295"));
	// The limit itself is a frame still to come.
	std::string buf = header(kAttachMagic, kAttachVersion, 1, kAttachMaxFrame) + "abc";
	assert_false(MUST(take_frame(buf)).has_value());
	assert_int_equal(buf.size(), kAttachHeader + 3);
}

void refused_truncated(void **)
{
	// A frame whose payload has not all come is not taken.
	const std::string whole = encode_frame(AttachType::Run, encode_run(typical_run()));
	std::string buf = whole.substr(0, whole.size() - 1);
	assert_false(MUST(take_frame(buf)).has_value());
	assert_int_equal(buf.size(), whole.size() - 1);

	// A payload cut short, or with a byte too many, is malformed.
	const std::string run = encode_run(typical_run());
	for (size_t cut : { size_t(0), size_t(7), size_t(8), size_t(12), run.size() - 1 }) {
		auto d = decode_run(run.substr(0, cut));
		assert_false(d.ok());
		assert_true(contains(d.error().message, "malformed run request"));
	}
	assert_false(decode_run(run + "x").ok());

	StartedReply s;
	const std::string started = encode_started(s);
	assert_int_equal(started.size(), 24);
	assert_true(contains(decode_started(started.substr(0, 23)).error().message, "malformed started reply"));
	assert_false(decode_started(started + "x").ok());

	EndedReply e;
	e.dropped = "why";
	const std::string ended = encode_ended(e);
	assert_true(contains(decode_ended(ended.substr(0, ended.size() - 1)).error().message, "malformed ended reply"));
	assert_int_equal(ended.size(), 56 + 4 + 3);
	assert_false(decode_ended(ended.substr(0, 56)).ok()); // no text length at all
	assert_false(decode_ended(ended + "x").ok());

	assert_true(contains(decode_signal(encode_signal(2).substr(0, 3)).error().message, "malformed signal request"));
	assert_false(decode_signal("").ok());
}

void refused_counts(void **)
{
	// argc and envc beyond what the payload can hold: refused before
	// anything is reserved for them.
	const std::string head = f64(0) + u32(4) + "/a/b" + u32(1) + "/";
	for (auto counts : { u32(UINT32_MAX) + u32(0), u32(0) + u32(UINT32_MAX), u32(UINT32_MAX) + u32(UINT32_MAX),
			     u32(2) + u32(0) + u32(1) + "x" }) {
		auto d = decode_run(head + counts);
		assert_false(d.ok());
		assert_true(contains(d.error().message, "counts larger than its payload"));
	}
	// A string's length beyond the payload.
	auto d = decode_run(f64(0) + u32(1u << 30) + "/a");
	assert_false(d.ok());
	assert_true(contains(d.error().message, "malformed run request"));
	// Counts that fit but strings that do not come.
	d = decode_run(head + u32(1) + u32(0) + u32(10) + "short");
	assert_false(d.ok());
}

void refused_run_requests(void **)
{
	assert_true(contains(run_refusal([](RunRequest &r) { r.path = "pendulum_pd"; }),
			     "the program's path is not absolute"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.path = ""; }), "the program's path is not absolute"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.path += std::string("\0x", 2); }), "a NUL inside a path"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.cwd = "work"; }),
			     "the working directory is not absolute"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.cwd = std::string("/tmp\0/x", 7); }),
			     "a NUL inside a path"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.env.push_back(std::string("A=\0b", 4)); }),
			     "a NUL inside an environment entry"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.argv.clear(); }), "no argv[0]"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.argv[1] = std::string("--sec\0onds", 10); }),
			     "a NUL inside an argument"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.env.push_back("NOEQUALS"); }),
			     "an environment entry without '='"));
	assert_true(contains(run_refusal([](RunRequest &r) { r.env.push_back(""); }), "without '='"));
	assert_false(decode_run(encode_run([] {
			     RunRequest r = typical_run();
			     r.env.push_back(std::string("A=b\0c", 5));
			     return r;
		     }())).ok());
	for (double bad : { -1.0, -5e-324, (double)NAN, -(double)NAN, (double)INFINITY, -(double)INFINITY }) {
		RunRequest r = typical_run();
		r.cpu_scale = bad;
		auto d = decode_run(encode_run(r));
		assert_false(d.ok());
		assert_true(contains(d.error().message, "the CPU scale"));
	}
}

void refused_signals(void **)
{
	for (int32_t bad : { 0, 65, -1, INT32_MIN, INT32_MAX }) {
		auto d = decode_signal(encode_signal(bad));
		assert_false(d.ok());
		assert_true(contains(d.error().message, "malformed signal request"));
	}
	assert_int_equal(MUST(decode_signal(encode_signal(1))), 1);
	assert_int_equal(MUST(decode_signal(encode_signal(64))), 64);
}

} // namespace

int main()
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(round_trip_frames),
		cmocka_unit_test(run_cpu_scales),
		cmocka_unit_test(run_large_environment),
		cmocka_unit_test(one_and_a_half_frames),
		cmocka_unit_test(refused_headers),
		cmocka_unit_test(refused_truncated),
		cmocka_unit_test(refused_counts),
		cmocka_unit_test(refused_run_requests),
		cmocka_unit_test(refused_signals),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
