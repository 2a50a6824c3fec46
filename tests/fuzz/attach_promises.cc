// The attach protocol's promises, checked (see attach_promises.h).
#include "attach_promises.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "fuzz_target.h"

namespace attach_promises {

namespace {

using tcs::AttachType;
using tcs_fuzz::check;

// An error the daemon sends back as REFUSED and logs: one printable line.
void check_reason(const std::string &why)
{
	check(!why.empty() && why.size() < 200);
	for (char c : why)
		check(c >= ' ' && c < 0x7F);
}

// What take_frame() must say of a buffer, worked out from the header alone.
enum class Verdict { Incomplete, Whole, Foreign };

Verdict expected_verdict(const std::string &buf, uint32_t *length)
{
	if (buf.size() < tcs::kAttachHeader)
		return Verdict::Incomplete;
	const uint64_t type = tcs_fuzz::get_le(buf, kTypeAt, 2);
	*length = uint32_t(tcs_fuzz::get_le(buf, kLengthAt, 4));
	if (tcs_fuzz::get_le(buf, kMagicAt, 4) != tcs::kAttachMagic ||
	    tcs_fuzz::get_le(buf, kVersionAt, 2) != tcs::kAttachVersion || type < uint64_t(AttachType::Run) ||
	    type > uint64_t(AttachType::Ended) || *length > tcs::kAttachMaxFrame)
		return Verdict::Foreign;
	return buf.size() < tcs::kAttachHeader + *length ? Verdict::Incomplete : Verdict::Whole;
}

// One call of take_frame() on buf, which holds bytes[consumed, ...): what
// it promises of the buffer. Its bytes are compared with the stream's at
// the end of feed(), not here, which would make a long stream quadratic.
tcs::Result<std::optional<tcs::AttachFrame>> take_checked(std::string &buf, const std::string &bytes,
							    size_t consumed)
{
	const size_t had = buf.size();
	uint32_t length = 0;
	const Verdict v = expected_verdict(buf, &length);
	auto f = tcs::take_frame(buf);
	if (!f) {
		check(v == Verdict::Foreign && buf.size() == had);
		check_reason(f.error().message);
		return f;
	}
	if (!*f) {
		// Nothing consumed, and nothing kept beyond one frame's worth.
		check(v == Verdict::Incomplete && buf.size() == had);
		check(had < tcs::kAttachHeader + tcs::kAttachMaxFrame);
		return f;
	}
	// Exactly one whole frame off the front: its header and payload.
	const tcs::AttachFrame &frame = **f;
	check(v == Verdict::Whole && frame.payload.size() == length);
	check(had - buf.size() == tcs::kAttachHeader + length);
	check(bytes.compare(consumed + tcs::kAttachHeader, length, frame.payload) == 0);
	check(uint64_t(frame.type) == tcs_fuzz::get_le(bytes, consumed + kTypeAt, 2));
	// Written again, the same header (but its reserved word, which is not
	// read) and payload.
	const std::string again = tcs::encode_frame(frame.type, frame.payload);
	check(again.size() == tcs::kAttachHeader + length);
	check(again.compare(0, 12, bytes, consumed, 12) == 0);
	check(again.compare(tcs::kAttachHeader, length, frame.payload) == 0);
	return f;
}

bool same_bits(double a, double b)
{
	return memcmp(&a, &b, sizeof a) == 0;
}

bool same_run(const tcs::RunRequest &a, const tcs::RunRequest &b)
{
	return same_bits(a.cpu_scale, b.cpu_scale) && a.path == b.path && a.cwd == b.cwd && a.argv == b.argv &&
	       a.env == b.env;
}

bool same_started(const tcs::StartedReply &a, const tcs::StartedReply &b)
{
	return a.id == b.id && a.pid == b.pid && a.mode == b.mode && a.fifo_cpu == b.fifo_cpu && a.v_start == b.v_start;
}

bool same_ended(const tcs::EndedReply &a, const tcs::EndedReply &b)
{
	return a.wait_status == b.wait_status && a.flags == b.flags && a.v_end == b.v_end &&
	       a.charged_ns == b.charged_ns && a.waits == b.waits && a.periodic_waits == b.periodic_waits &&
	       a.deadline_misses == b.deadline_misses && a.preemptions == b.preemptions && a.dropped == b.dropped;
}

bool c_string(const std::string &s)
{
	return s.find('\0') == std::string::npos;
}

// A refusal names what was malformed.
void check_refusal(const tcs::Error &e, const char *what)
{
	check_reason(e.message);
	check(e.message.rfind(std::string("malformed ") + what, 0) == 0);
}

} // namespace

Outcome feed(const std::string &bytes, size_t piece)
{
	Outcome o;
	size_t consumed = 0, fed = 0;
	while (fed < bytes.size() && !o.error) {
		const size_t n = std::min(piece, bytes.size() - fed);
		o.left.append(bytes, fed, n);
		fed += n;
		for (;;) {
			auto f = take_checked(o.left, bytes, consumed);
			if (!f) {
				o.error = f.error().message;
				break;
			}
			if (!*f)
				break;
			consumed += tcs::kAttachHeader + (**f).payload.size();
			o.frames.push_back(std::move(**f));
		}
	}
	// The buffer is the stream's bytes not yet taken, unchanged.
	check(o.left.size() == fed - consumed && bytes.compare(consumed, fed - consumed, o.left) == 0);
	return o;
}

bool same_outcome(const Outcome &a, const Outcome &b)
{
	if (a.frames.size() != b.frames.size() || a.error != b.error)
		return false;
	for (size_t i = 0; i < a.frames.size(); i++)
		if (a.frames[i].type != b.frames[i].type || a.frames[i].payload != b.frames[i].payload)
			return false;
	// A refused stream stops where its bad header arrived; the rest differs.
	return a.error || a.left == b.left;
}

// A run request the daemon hands to spawn: it execs path in cwd with
// argv and env as C strings, and takes cpu_scale as a factor.
void check_run(const std::string &payload)
{
	auto r = tcs::decode_run(payload);
	if (!r) {
		check_refusal(r.error(), "run request");
		return;
	}
	check(!r->path.empty() && r->path[0] == '/' && c_string(r->path));
	check(!r->cwd.empty() && r->cwd[0] == '/' && c_string(r->cwd));
	check(!r->argv.empty());
	for (const auto &a : r->argv)
		check(c_string(a));
	for (const auto &e : r->env)
		check(c_string(e) && e.find('=') != std::string::npos);
	check(r->cpu_scale == 0 || (std::isfinite(r->cpu_scale) && r->cpu_scale > 0));
	const std::string again = tcs::encode_run(*r);
	check(again == payload); // one way to write each request
	auto back = tcs::decode_run(again);
	check(back && same_run(*back, *r));
}

void check_started(const std::string &payload)
{
	auto r = tcs::decode_started(payload);
	if (!r) {
		check_refusal(r.error(), "started reply");
		return;
	}
	const std::string again = tcs::encode_started(*r);
	check(again == payload);
	auto back = tcs::decode_started(again);
	check(back && same_started(*back, *r));
}

void check_ended(const std::string &payload)
{
	auto r = tcs::decode_ended(payload);
	if (!r) {
		check_refusal(r.error(), "ended reply");
		return;
	}
	const std::string again = tcs::encode_ended(*r);
	check(again == payload);
	auto back = tcs::decode_ended(again);
	check(back && same_ended(*back, *r));
}

void check_signal(const std::string &payload)
{
	auto r = tcs::decode_signal(payload);
	if (!r) {
		check_refusal(r.error(), "signal request");
		return;
	}
	check(*r >= 1 && *r <= 64); // kill()'s range, 0 (a probe) excluded
	const std::string again = tcs::encode_signal(*r);
	check(again == payload);
	auto back = tcs::decode_signal(again);
	check(back && *back == *r);
}

} // namespace attach_promises
