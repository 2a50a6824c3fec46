// The fuzz target for the attach protocol (coordinator/attach_protocol.h):
// an input is what a client wrote on coordinatord's socket. It is taken
// apart by take_frame() whole and in pieces, as recv_some() delivers a
// stream, and every payload goes through each decoder, as the daemon (RUN,
// SIGNAL) and tcs-run (STARTED, ENDED) decode them. A frame taken is
// exactly its header and payload; a value decoded holds what the daemon
// relies on (absolute paths, argv[0], environment entries, CPU scale) and
// is encoded again byte for byte (attach_promises.cc checks all that). A
// new frame type needs its decoder there and a seed here.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "attach_promises.h"
#include "attach_protocol.h"
#include "fuzz_target.h"

namespace {

using namespace attach_promises;
using tcs::AttachType;
using tcs_fuzz::check;

// ---- Seeds ----

std::string le(uint64_t v, int bytes)
{
	std::string s(size_t(bytes), '\0');
	tcs_fuzz::put_le(s, 0, v, bytes);
	return s;
}

std::string f64(double v)
{
	std::string s(sizeof v, '\0');
	memcpy(s.data(), &v, sizeof v);
	return s;
}

// A header as anyone may write it, true or not.
std::string header(uint64_t magic, uint64_t version, uint64_t type, uint64_t length, uint64_t reserved = 0)
{
	return le(magic, 4) + le(version, 2) + le(type, 2) + le(length, 4) + le(reserved, 4);
}

std::string frame(AttachType type, const std::string &payload)
{
	return tcs::encode_frame(type, payload);
}

tcs::RunRequest typical_run()
{
	tcs::RunRequest r;
	r.path = "/usr/local/bin/pendulum_pd";
	r.cwd = "/home/robot/work";
	r.argv = { "pendulum_pd", "--seconds", "10" };
	r.env = { "PATH=/usr/local/bin:/usr/bin", "HOME=/home/robot", "EMPTY=", "A==b" };
	return r;
}

std::string run_payload(void (*edit)(tcs::RunRequest &))
{
	tcs::RunRequest r = typical_run();
	edit(r);
	return tcs::encode_run(r);
}

// Where a payload's 4-byte counts and lengths are, read as a run request
// as far as it goes (cpu_scale, path, cwd, argc, envc, then the strings).
std::vector<size_t> run_length_fields(const std::string &p)
{
	std::vector<size_t> at;
	size_t pos = 8;
	auto string_at = [&]() {
		if (pos + 4 > p.size())
			return false;
		at.push_back(pos);
		pos += 4 + tcs_fuzz::get_le(p, pos, 4);
		return pos <= p.size();
	};
	if (!string_at() || !string_at() || pos + 8 > p.size())
		return at;
	uint64_t count = tcs_fuzz::get_le(p, pos, 4) + tcs_fuzz::get_le(p, pos + 4, 4);
	at.push_back(pos);
	at.push_back(pos + 4);
	pos += 8;
	while (count-- > 0 && string_at())
		; // each string at least its length: this ends with the payload
	return at;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const std::string bytes(reinterpret_cast<const char *>(data), size);
	// As recv_some() reads it, then in other pieces: the same frames and the
	// same refusal however the stream is cut. Whole and byte by byte only
	// where that stays quick (each frame taken moves the rest of the buffer).
	const Outcome as_read = feed(bytes, kRecvSize);
	if (size <= 4 * kRecvSize)
		check(same_outcome(as_read, feed(bytes, size ? size : 1)));
	if (size <= 20000)
		check(same_outcome(as_read, feed(bytes, 1)));
	else
		check(same_outcome(as_read, feed(bytes, 4093)));

	// Each payload, through every decoder: any frame may carry anything.
	for (const auto &f : as_read.frames) {
		check_run(f.payload);
		check_started(f.payload);
		check_ended(f.payload);
		check_signal(f.payload);
	}
	// Left over behind the frames: a payload as well, as a decoder sees it.
	if (as_read.left.size() <= tcs::kAttachMaxFrame) {
		check_run(as_read.left);
		check_signal(as_read.left);
	}
	return 0;
}

const char *tcs_fuzz_name()
{
	return "attach_fuzz";
}

std::vector<std::string> tcs_fuzz_seeds()
{
	using T = AttachType;
	const uint32_t M = tcs::kAttachMagic, V = tcs::kAttachVersion;

	tcs::StartedReply started;
	started.id = 3;
	started.pid = 4242;
	started.mode = 1;
	started.fifo_cpu = 7;
	started.v_start = 5'000'000'000;
	tcs::StartedReply no_fifo;
	no_fifo.fifo_cpu = -1;
	no_fifo.v_start = INT64_MAX;
	tcs::EndedReply ended;
	ended.wait_status = 0x100; // exited 1
	ended.flags = tcs::kEndedAttached;
	ended.v_end = 15'000'000'000;
	ended.charged_ns = 63'778'000;
	ended.waits = 10001;
	ended.periodic_waits = 10001;
	ended.deadline_misses = 2;
	ended.preemptions = 5;
	tcs::EndedReply dropped;
	dropped.wait_status = -1;
	dropped.flags = tcs::kEndedByTcs;
	dropped.dropped = "it sent a malformed message";
	dropped.waits = UINT64_MAX;

	const std::string run = tcs::encode_run(typical_run());
	const std::string run_frame = frame(T::Run, run);
	std::vector<std::string> v = {
		// Every type, valid.
		run_frame,
		frame(T::Run, run_payload([](tcs::RunRequest &r) {
			      r.cpu_scale = 3;
			      r.argv.push_back("");
			      r.env.clear();
		      })),
		frame(T::Signal, tcs::encode_signal(2)),
		frame(T::Signal, tcs::encode_signal(64)),
		frame(T::Started, tcs::encode_started(started)),
		frame(T::Started, tcs::encode_started(no_fifo)),
		frame(T::Refused, "coordinatord serves uid 1000 only, not uid 0"),
		frame(T::Ended, tcs::encode_ended(ended)),
		frame(T::Ended, tcs::encode_ended(dropped)),
		// A conversation in one stream, each way.
		run_frame + frame(T::Signal, tcs::encode_signal(2)) + frame(T::Signal, tcs::encode_signal(9)),
		frame(T::Started, tcs::encode_started(started)) + frame(T::Ended, tcs::encode_ended(ended)),
		// Requests the daemon refuses.
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.path = "pendulum_pd"; })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.cwd = ""; })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.path += std::string("\0x", 2); })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.argv.clear(); })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.argv[1] = std::string("--sec\0onds", 10); })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.env.push_back("NOEQUALS"); })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.cpu_scale = -1; })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.cpu_scale = NAN; })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.cpu_scale = INFINITY; })),
		frame(T::Run, run_payload([](tcs::RunRequest &r) { r.cpu_scale = -0.0; })),
		frame(T::Signal, tcs::encode_signal(0)),
		frame(T::Signal, tcs::encode_signal(65)),
		frame(T::Signal, tcs::encode_signal(-1)),
		frame(T::Run, run + "x"), // one byte too many
		frame(T::Run, run.substr(0, run.size() - 1)),
		frame(T::Started, ""),
		frame(T::Ended, ""),
		// Counts and lengths that lie: argc, a string's length.
		frame(T::Run, f64(0) + le(4, 4) + "/a/b" + le(1, 4) + "/" + le(UINT32_MAX, 4) + le(UINT32_MAX, 4)),
		frame(T::Run, f64(0) + le(1u << 30, 4) + "/a"),
		frame(T::Ended, tcs::encode_ended(ended).substr(0, kEndedTextAt) + le(1000, 4) + "short"),
		// Headers that lie or are foreign.
		header(M, V, uint16_t(T::Run), tcs::kAttachMaxFrame + 1),
		header(M, V, uint16_t(T::Run), UINT32_MAX) + run,
		header(M, V, uint16_t(T::Run), tcs::kAttachMaxFrame) + run, // incomplete, never whole
		header(M, V, uint16_t(T::Run), run.size() + 100) + run,
		header(M, V + 1, uint16_t(T::Run), run.size()) + run,
		header(M, 0, uint16_t(T::Signal), 4) + le(2, 4),
		header(M ^ 0xFF000000u, V, uint16_t(T::Run), run.size()) + run,
		header(M, V, 0, 0),
		header(M, V, uint16_t(T::Ended) + 1, 0),
		header(M, V, uint16_t(T::Signal), 4, UINT32_MAX) + le(15, 4), // reserved word set
		header(M, V, uint16_t(T::Refused), 0),
		run_frame.substr(0, tcs::kAttachHeader - 1),
		"GET / HTTP/1.1\r\nHost: localhost\r\n\r\n",
		"",
	};
	// A large environment, as a login shell's may be.
	tcs::RunRequest big = typical_run();
	for (int i = 0; i < 600; i++)
		big.env.push_back("VAR_" + std::to_string(i) + "=" + std::string(100, char('a' + i % 26)));
	v.push_back(frame(T::Run, tcs::encode_run(big)));
	return v;
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { le(tcs::kAttachMagic, 4),
		 le(tcs::kAttachVersion, 2),
		 le(uint16_t(AttachType::Run), 2),
		 le(uint16_t(AttachType::Signal), 2),
		 le(uint16_t(AttachType::Ended), 2),
		 le(uint16_t(AttachType::Ended) + 1, 2),
		 le(tcs::kAttachMaxFrame, 4),
		 le(tcs::kAttachMaxFrame + 1, 4),
		 le(UINT32_MAX, 4),
		 le(0, 4),
		 header(tcs::kAttachMagic, tcs::kAttachVersion, uint16_t(AttachType::Run), 0),
		 "/",
		 "=",
		 std::string(1, '\0'),
		 "PATH=/usr/bin",
		 f64(NAN),
		 f64(-1),
		 f64(-0.0),
		 f64(INFINITY),
		 f64(5e-324) };
}

// A length, count or field of one frame made to lie: the header's length
// or type, a run request's counts or string lengths, its CPU scale, an
// ended reply's text length, a signal number.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	// The frames the input holds, by their own lengths.
	std::vector<size_t> starts;
	for (size_t at = 0; at + tcs::kAttachHeader <= s.size();) {
		starts.push_back(at);
		at += tcs::kAttachHeader + tcs_fuzz::get_le(s, at + kLengthAt, 4);
	}
	if (starts.empty())
		return false;
	const size_t at = starts[rng.below(starts.size())];
	const size_t payload_at = at + tcs::kAttachHeader;
	const std::string payload =
		s.substr(payload_at, size_t(std::min<uint64_t>(tcs_fuzz::get_le(s, at + kLengthAt, 4), s.size())));
	switch (rng.below(5)) {
	case 0: // the header's length
		tcs_fuzz::put_le(s, at + kLengthAt,
				 rng.below(2) ? tcs_fuzz::lying_value(rng, payload.size())
					      : payload.size() + rng.below(9) - 4,
				 4);
		break;
	case 1: // the header's type or version
		tcs_fuzz::put_le(s, at + (rng.below(4) ? kTypeAt : kVersionAt), rng.below(8), 2);
		break;
	case 2: { // a run request's count or string length
		const std::vector<size_t> fields = run_length_fields(payload);
		if (fields.empty())
			return false;
		const size_t f = fields[rng.below(fields.size())];
		const uint64_t now = tcs_fuzz::get_le(payload, f, 4);
		tcs_fuzz::put_le(s, payload_at + f,
				 rng.below(2) ? tcs_fuzz::lying_value(rng, payload.size()) : now + rng.below(5) - 2, 4);
		break;
	}
	case 3: { // a run request's CPU scale
		const double scales[] = { 0.0, -0.0, 1.0, -1.0, NAN, -NAN, INFINITY, -INFINITY, 5e-324, 1e308 };
		uint64_t bits;
		memcpy(&bits, &scales[rng.below(sizeof scales / sizeof scales[0])], sizeof bits);
		tcs_fuzz::put_le(s, payload_at, bits, 8);
		break;
	}
	case 4: // a signal number, or an ended reply's text length
		tcs_fuzz::put_le(s, payload_at + (rng.below(2) ? 0 : kEndedTextAt),
				 rng.below(2) ? tcs_fuzz::lying_value(rng, payload.size()) : rng.below(67), 4);
		break;
	}
	return true;
}
