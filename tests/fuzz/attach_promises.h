// The promises the attach protocol keeps (coordinator/attach_protocol.h),
// checked for the fuzz target: frames taken off a stream, however it is
// cut, are exactly their header and payload; every decoder's result holds
// what its reader relies on and encodes back to the same bytes; a refusal
// is one printable line. A broken promise aborts (tcs_fuzz::check).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "attach_protocol.h"

namespace attach_promises {

// The header's fields, at these offsets (attach_protocol.cc writes them in
// the host's byte order, read here as little-endian: x86-64 and arm64).
inline constexpr size_t kMagicAt = 0, kVersionAt = 4, kTypeAt = 6, kLengthAt = 8;

// An ended reply's text length: after two 32-bit and six 64-bit fields.
inline constexpr size_t kEndedTextAt = 4 + 4 + 6 * 8;

// recv_some() reads this much at a time.
inline constexpr size_t kRecvSize = 16384;

struct Outcome {
	std::vector<tcs::AttachFrame> frames;
	std::optional<std::string> error; // the stream was refused here
	std::string left;                 // what waits for more bytes
};

// The stream as it arrives in pieces of `piece` bytes: after each, frames
// are taken until none is whole, as Clients::on_readable does.
Outcome feed(const std::string &bytes, size_t piece);
bool same_outcome(const Outcome &a, const Outcome &b);

// A payload through each decoder, as the daemon (RUN, SIGNAL) and tcs-run
// (STARTED, ENDED) decode them.
void check_run(const std::string &payload);
void check_started(const std::string &payload);
void check_ended(const std::string &payload);
void check_signal(const std::string &payload);

} // namespace attach_promises
