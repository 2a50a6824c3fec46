// The attach protocol between `tcs-run --connect` and coordinatord, defined
// once for both sides. A stream of frames on a Unix socket, each a 16-byte
// header and its payload:
//
//   tcs-run -> daemon  RUN     program, argv, environment, working directory,
//                              CPU scale; stdin/stdout/stderr ride along as
//                              SCM_RIGHTS on the frame's first bytes
//                      SIGNAL  a signal for the controller (Ctrl-C at tcs-run)
//   daemon -> tcs-run  STARTED it runs: id, pid, where the world was
//                      REFUSED why not (text); the daemon closes
//                      ENDED   how it ended and what it did; the daemon closes
//
// Everything a client sends is untrusted: decoding checks every length.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "error.h"

namespace tcs {

constexpr uint32_t kAttachMagic = 0x41534354; // "TCSA"
constexpr uint16_t kAttachVersion = 1;
constexpr size_t kAttachHeader = 16;
constexpr size_t kAttachMaxFrame = 1 << 20; // an environment of 1 MiB is plenty

enum class AttachType : uint16_t { Run = 1, Signal = 2, Started = 3, Refused = 4, Ended = 5 };

struct AttachFrame {
	AttachType type = AttachType::Run;
	std::string payload;
};

struct RunRequest {
	std::string path; // absolute, resolved by tcs-run in its own directory
	std::string cwd;
	std::vector<std::string> argv;
	std::vector<std::string> env;
	double cpu_scale = 0; // 0: the daemon's choice (the scenario's, else 1)
};

struct StartedReply {
	int32_t id = 0;
	int32_t pid = 0;
	int32_t mode = 0; // TCS_MODE_*
	int32_t fifo_cpu = -1; // the core under SCHED_FIFO, -1 without
	int64_t v_start = 0;
};

struct EndedReply {
	int32_t wait_status = -1; // as from waitpid; -1: it never ended by itself
	uint32_t flags = 0;       // kEnded*
	int64_t v_end = 0, charged_ns = 0;
	uint64_t waits = 0, periodic_waits = 0, deadline_misses = 0, preemptions = 0;
	std::string dropped; // non-empty: tcs dropped it, and why
};
constexpr uint32_t kEndedByTcs = 1;   // ended by the daemon's end
constexpr uint32_t kEndedAttached = 2; // libtcs_preload reported in

// A whole frame, header included.
std::string encode_frame(AttachType type, std::string_view payload);
// Takes the first whole frame off the front of buf; none yet if it is
// incomplete; an error for a foreign or oversized one.
Result<std::optional<AttachFrame>> take_frame(std::string &buf);

std::string encode_run(const RunRequest &r);
Result<RunRequest> decode_run(std::string_view payload);
std::string encode_started(const StartedReply &r);
Result<StartedReply> decode_started(std::string_view payload);
std::string encode_ended(const EndedReply &r);
Result<EndedReply> decode_ended(std::string_view payload);
std::string encode_signal(int32_t signo);
Result<int32_t> decode_signal(std::string_view payload);

} // namespace tcs
