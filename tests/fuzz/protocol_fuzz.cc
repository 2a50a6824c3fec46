// The fuzz target for the wire protocol's decoder: an input is a datagram
// a controller sent, received as on_channel (coordinator/messages.cc)
// receives it (into a buffer one byte longer than a message, so a longer
// one arrives cut to that) and passed through tcs_msg_check(). What it accepts must hold every
// promise the coordinator's handlers rely on; what it rejects must come
// with a reason fit for "bad message on its channel: <reason>". A new
// message type needs its case in check_accepted() and a seed.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "fuzz_target.h"
#include "tcs/protocol.h"
#include "tcs/vtime.h"

namespace {

using tcs_fuzz::check;

void check_reason(const char *why)
{
	const size_t len = strlen(why);
	check(len > 0 && len < 100);
	for (size_t i = 0; i < len; i++)
		check(why[i] >= ' ' && why[i] < 0x7F); // one printable line
}

// What each handler does with the fields of an accepted message: they
// index, compare and add without checking again.
void check_accepted(const tcs_msg &m)
{
	check(m.magic == TCS_PROTO_MAGIC && m.version == TCS_PROTO_VERSION);
	switch (m.type) {
	case TCS_MSG_HELLO:
		// Compared with the controller's pid_t.
		check(m.arg > 0 && m.arg <= INT32_MAX);
		break;
	case TCS_MSG_BLOCK:
		// The wait's kind names it in the trace; times are added and
		// compared as non-negative virtual ns (TCS_NEVER included).
		check(m.kind == TCS_BLOCK_SLEEP || m.kind == TCS_BLOCK_POLL || m.kind == TCS_BLOCK_SYNC ||
		      m.kind == TCS_BLOCK_SPIN);
		check((m.flags & ~TCS_BLOCK_FLAGS_ALL) == 0);
		check(m.deadline >= 0 && m.v >= 0 && m.cpu >= 0 && m.slack >= 0);
		check(tcs_ns_add(m.v, m.deadline) >= m.deadline);
		break;
	case TCS_MSG_EARLY:
		check(m.kind == TCS_EARLY_FD || m.kind == TCS_EARLY_SIGNAL);
		break;
	case TCS_MSG_DEV_OPEN:
		// (size_t)arg indexes the scenario's devices.
		check(m.arg >= 0 && m.arg < TCS_MAX_DEVICES);
		check((m.flags & ~TCS_DEV_FLAGS_ALL) == 0 && (m.flags & (TCS_DEV_READ | TCS_DEV_WRITE)));
		break;
	case TCS_MSG_DEV_SYNC:
		// (size_t)arg indexes the controller's open devices; a handle
		// fits the int the preload keeps it in.
		check(m.kind == TCS_SYNC_READ || m.kind == TCS_SYNC_WRITE || m.kind == TCS_SYNC_POLL ||
		      m.kind == TCS_SYNC_DRAIN);
		check((m.flags & ~TCS_DEV_FLAGS_ALL) == 0);
		// A wire's read waits until its deadline at most: never one before 0.
		check(!(m.flags & TCS_DEV_DEADLINE) || m.deadline >= 0);
		check(m.arg >= 0 && m.arg <= INT32_MAX && m.v >= 0 && m.cpu >= 0);
		break;
	case TCS_MSG_TIMER:
		// flags indexes the controller's timer slots, kind is a signal,
		// v a thread id (0: the process), arg a period in ns.
		check(m.flags < TCS_MAX_TIMERS && m.kind >= 1 && m.kind <= 64);
		check(m.deadline >= 0 && m.arg >= 0 && m.v >= 0 && m.v <= INT32_MAX && m.cpu >= 0);
		break;
	case TCS_MSG_CHILD:
		// A pid, a virtual time, and flags the coordinator knows.
		check(m.arg > 0 && m.arg <= INT32_MAX && m.v >= 0 && m.cpu >= 0);
		check((m.flags & ~(TCS_CHILD_V_KNOWN | TCS_CHILD_PARENT)) == 0);
		break;
	case TCS_MSG_THREAD:
		// A thread id, compared with /proc's.
		check(m.arg > 0 && m.arg <= INT32_MAX);
		break;
	case TCS_MSG_KILL:
		// kill()'s pid argument (a process, a group, all) and the sender's time.
		check(m.arg >= -(int64_t)INT32_MAX && m.arg <= INT32_MAX && m.v >= 0 && m.cpu >= 0);
		break;
	case TCS_MSG_DOORBELL:
		break; // only its type is read (look at the mailbox)
	default:
		check(false); // WAKE and unknown types are never accepted
	}
}

// Every field as a preload writes it: the same bytes, accepted again.
void check_rebuilt(const tcs_msg &m)
{
	tcs_msg w = tcs_msg_make(m.type, m.seq);
	w.kind = m.kind;
	w.flags = m.flags;
	w.deadline = m.deadline;
	w.v = m.v;
	w.cpu = m.cpu;
	w.arg = m.arg;
	w.slack = m.slack;
	check(memcmp(&w, &m, sizeof m) == 0);
	tcs_msg again;
	check(tcs_msg_check(&w, (long)sizeof w, &again) == nullptr);
	check(memcmp(&again, &m, sizeof m) == 0);
}

// One message of a type, its fields set as the preload sets them.
std::string message(uint16_t type, uint16_t kind, uint16_t flags, int64_t deadline, int64_t v, int64_t cpu,
		    int64_t arg, uint32_t seq = 7)
{
	tcs_msg m = tcs_msg_make(type, seq);
	m.kind = kind;
	m.flags = flags;
	m.deadline = deadline;
	m.v = v;
	m.cpu = cpu;
	m.arg = arg;
	return std::string(reinterpret_cast<const char *>(&m), sizeof m);
}

std::string le(uint64_t v, int bytes)
{
	std::string s(size_t(bytes), '\0');
	tcs_fuzz::put_le(s, 0, v, bytes);
	return s;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	// As on_channel receives it: at most one byte more than a message.
	alignas(8) unsigned char buf[sizeof(struct tcs_msg) + 1];
	const size_t n = size < sizeof buf ? size : sizeof buf;
	memcpy(buf, data, n);
	tcs_msg m;
	const char *why = tcs_msg_check(buf, (long)n, &m);
	if (why) {
		check_reason(why);
		check(n != sizeof m || strcmp(why, "wrong size") != 0);
	} else {
		check(n == sizeof m && memcmp(&m, data, sizeof m) == 0);
		check_accepted(m);
		check_rebuilt(m);
	}
	// The input itself, of any length, unaligned: the same verdict when it
	// is a whole message, "wrong size" otherwise.
	std::unique_ptr<unsigned char[]> odd(new unsigned char[size + 1]); // ends where the input does
	if (size)
		memcpy(odd.get() + 1, data, size);
	tcs_msg direct;
	const char *why_direct = tcs_msg_check(odd.get() + 1, (long)size, &direct);
	if (size == sizeof direct)
		check((why == nullptr) == (why_direct == nullptr) && (!why || strcmp(why, why_direct) == 0));
	else
		check(why_direct && strcmp(why_direct, "wrong size") == 0);
	// A failed receive.
	check(tcs_msg_check(data, -1, &direct) != nullptr);
	return 0;
}

const char *tcs_fuzz_name()
{
	return "protocol_fuzz";
}

std::vector<std::string> tcs_fuzz_seeds()
{
	const int64_t s = TCS_NS_PER_S;
	std::vector<std::string> v = {
		message(TCS_MSG_HELLO, 0, 0, 0, 0, 0, 4242, 0),
		message(TCS_MSG_HELLO, 0, 0, 0, 0, 0, INT32_MAX, 0),
		message(TCS_MSG_BLOCK, TCS_BLOCK_SLEEP, 0, 5 * s, 4 * s, 123456789, 0),
		message(TCS_MSG_BLOCK, TCS_BLOCK_SLEEP, TCS_BLOCK_ABSOLUTE, 5 * s, 4 * s, 1, 0),
		message(TCS_MSG_BLOCK, TCS_BLOCK_POLL, TCS_BLOCK_RECHECK | TCS_BLOCK_DEVICES, TCS_NEVER, 0, 0, 0),
		message(TCS_MSG_BLOCK, TCS_BLOCK_POLL, TCS_BLOCK_FLAGS_ALL, 0, TCS_NEVER, TCS_NEVER, 0, UINT32_MAX),
		message(TCS_MSG_EARLY, TCS_EARLY_FD, 0, 0, 0, 0, 0),
		message(TCS_MSG_EARLY, TCS_EARLY_SIGNAL, 0, 0, 0, 0, 0),
		message(TCS_MSG_DEV_OPEN, 0, TCS_DEV_READ, 0, 0, 5, 0),
		message(TCS_MSG_DEV_OPEN, 0, TCS_DEV_WRITE | TCS_DEV_NONBLOCK, 0, 0, 5, TCS_MAX_DEVICES - 1),
		message(TCS_MSG_DEV_OPEN, 0, TCS_DEV_FLAGS_ALL, 0, 0, 5, 3),
		message(TCS_MSG_DEV_SYNC, TCS_SYNC_READ, TCS_DEV_NONBLOCK, 0, s, s, 0),
		message(TCS_MSG_DEV_SYNC, TCS_SYNC_WRITE, 0, 0, s, s, 1),
		message(TCS_MSG_DEV_SYNC, TCS_SYNC_POLL, 0, 0, 0, 0, INT32_MAX),
		message(TCS_MSG_WAKE, TCS_WAKE_DEADLINE, 0, 0, s, 0, 0), // the coordinator's own: refused
	};
	v.push_back(message(TCS_MSG_TIMER, 14, 0, 5 * s, 0, 1, 0));                        // alarm(5)
	v.push_back(message(TCS_MSG_TIMER, 26, TCS_MAX_TIMERS - 1, s, 1234, 1, s / 100)); // a thread's periodic timer
	v.push_back(message(TCS_MSG_TIMER, 64, 1, TCS_NEVER, INT32_MAX, 0, 0));            // disarmed
	v.push_back(message(TCS_MSG_CHILD, 0, TCS_CHILD_V_KNOWN, 0, 3 * s, 0, 4243));
	v.push_back(message(TCS_MSG_CHILD, 0, TCS_CHILD_PARENT, 0, 0, 0, INT32_MAX));
	v.push_back(message(TCS_MSG_THREAD, 0, 0, 0, 0, 0, 4244));
	v.push_back(message(TCS_MSG_KILL, 0, 0, 0, 2 * s, s, 4245));       // kill(4245, ...)
	v.push_back(message(TCS_MSG_KILL, 0, 0, 0, 0, 0, -1));             // kill(-1, ...)
	v.push_back(message(TCS_MSG_KILL, 0, 0, 0, 0, 0, -INT32_MAX));     // killpg(INT32_MAX, ...)
	v.push_back(v[2].substr(0, sizeof(tcs_msg) - 1)); // one byte short
	v.push_back(v[2] + '\0');                          // one byte long
	v.push_back(v[2] + v[2]);                          // two at once
	v.push_back("");
	return v;
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { le(TCS_PROTO_MAGIC, 4), le(TCS_PROTO_VERSION, 2), le(TCS_MSG_WAKE, 2), le(TCS_MSG_DEV_SYNC, 2),
		 le(uint64_t(TCS_NEVER), 8), le(uint64_t(INT32_MAX) + 1, 8), le(uint64_t(-1), 8), le(TCS_MAX_DEVICES, 8) };
}

// A field of the message set to a value next to a limit it is checked against.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	if (s.size() < sizeof(tcs_msg))
		return false;
	struct Field {
		size_t at;
		int bytes;
	};
	const Field fields[] = { { 0, 4 }, { 4, 2 }, { 6, 2 }, { 8, 4 }, { 12, 2 }, { 14, 2 },
				 { 16, 8 }, { 24, 8 }, { 32, 8 }, { 40, 8 }, { 48, 8 } };
	const uint64_t values[] = { 0,
				    1,
				    2,
				    3,
				    4,
				    5,
				    6,
				    7,
				    uint64_t(-1),
				    TCS_MAX_DEVICES - 1,
				    TCS_MAX_DEVICES,
				    INT32_MAX,
				    uint64_t(INT32_MAX) + 1,
				    uint64_t(TCS_NEVER),
				    uint64_t(INT64_MIN),
				    TCS_PROTO_MAGIC,
				    TCS_BLOCK_FLAGS_ALL + 1,
				    TCS_DEV_FLAGS_ALL + 1 };
	const Field f = fields[rng.below(sizeof fields / sizeof fields[0])];
	uint64_t v = values[rng.below(sizeof values / sizeof values[0])];
	if (rng.below(4) == 0)
		v = uint64_t(1) << rng.below(size_t(8 * f.bytes)); // one flag bit
	tcs_fuzz::put_le(s, f.at, v, f.bytes);
	return true;
}
