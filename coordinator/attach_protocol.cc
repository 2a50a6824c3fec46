// Encoding and checked decoding of attach frames. Both ends are on one
// host, so fixed fields travel in the host's byte order; strings as a
// 32-bit length and their bytes.
#include "attach_protocol.h"

#include <cmath>
#include <cstring>

namespace tcs {

namespace {

class Writer {
public:
	template <class T> Writer &put(T v)
	{
		out.append(reinterpret_cast<const char *>(&v), sizeof v);
		return *this;
	}
	Writer &str(std::string_view s)
	{
		put((uint32_t)s.size());
		out.append(s);
		return *this;
	}
	std::string out;
};

// Reads fields off a payload; the first short read makes every later one
// fail too, so a decoder checks once at the end.
class Reader {
public:
	explicit Reader(std::string_view in) : in_(in) {}
	template <class T> T get()
	{
		T v{};
		if (in_.size() < sizeof v) {
			bad_ = true;
			in_ = {};
			return v;
		}
		std::memcpy(&v, in_.data(), sizeof v);
		in_.remove_prefix(sizeof v);
		return v;
	}
	std::string str()
	{
		uint32_t n = get<uint32_t>();
		if (bad_ || n > in_.size()) {
			bad_ = true;
			in_ = {};
			return {};
		}
		std::string s(in_.substr(0, n));
		in_.remove_prefix(n);
		return s;
	}
	// Everything read, nothing short, nothing left over.
	bool done() const { return !bad_ && in_.empty(); }
	size_t left() const { return in_.size(); }

private:
	std::string_view in_;
	bool bad_ = false;
};

Error bad(const char *what)
{
	return Error{ std::string("malformed ") + what };
}

// A C string: no NUL inside (exec would cut it short).
bool clean(const std::string &s)
{
	return s.find('\0') == std::string::npos;
}

} // namespace

std::string encode_frame(AttachType type, std::string_view payload)
{
	Writer w;
	w.put(kAttachMagic).put(kAttachVersion).put((uint16_t)type).put((uint32_t)payload.size()).put(uint32_t{ 0 });
	w.out.append(payload);
	return w.out;
}

Result<std::optional<AttachFrame>> take_frame(std::string &buf)
{
	if (buf.size() < kAttachHeader)
		return std::optional<AttachFrame>{};
	Reader r(std::string_view(buf).substr(0, kAttachHeader));
	uint32_t magic = r.get<uint32_t>();
	uint16_t version = r.get<uint16_t>();
	uint16_t type = r.get<uint16_t>();
	uint32_t length = r.get<uint32_t>();
	if (magic != kAttachMagic)
		return Error{ "not a tcs attach request" };
	if (version != kAttachVersion)
		return Error{ "attach protocol version " + std::to_string(version) + ", this is version " +
			      std::to_string(kAttachVersion) + " (tcs-run and coordinatord differ)" };
	if (type < (uint16_t)AttachType::Run || type > (uint16_t)AttachType::Ended)
		return Error{ "unknown attach frame type " + std::to_string(type) };
	if (length > kAttachMaxFrame)
		return Error{ "attach frame of " + std::to_string(length) + " bytes (the limit is " +
			      std::to_string(kAttachMaxFrame) + ")" };
	if (buf.size() < kAttachHeader + length)
		return std::optional<AttachFrame>{};
	AttachFrame f;
	f.type = (AttachType)type;
	f.payload = buf.substr(kAttachHeader, length);
	buf.erase(0, kAttachHeader + length);
	return std::optional<AttachFrame>(std::move(f));
}

std::string encode_run(const RunRequest &r)
{
	Writer w;
	w.put(r.cpu_scale).str(r.path).str(r.cwd).put((uint32_t)r.argv.size()).put((uint32_t)r.env.size());
	for (const auto &a : r.argv)
		w.str(a);
	for (const auto &e : r.env)
		w.str(e);
	return w.out;
}

Result<RunRequest> decode_run(std::string_view payload)
{
	Reader rd(payload);
	RunRequest r;
	r.cpu_scale = rd.get<double>();
	r.path = rd.str();
	r.cwd = rd.str();
	uint32_t argc = rd.get<uint32_t>();
	uint32_t envc = rd.get<uint32_t>();
	// Each string costs at least its 4-byte length: counts beyond what the
	// payload can hold are lies, refused before anything is reserved.
	if ((uint64_t)argc + envc > rd.left() / 4)
		return bad("run request (counts larger than its payload)");
	for (uint32_t i = 0; i < argc; i++)
		r.argv.push_back(rd.str());
	for (uint32_t i = 0; i < envc; i++)
		r.env.push_back(rd.str());
	if (!rd.done())
		return bad("run request");
	if (r.path.empty() || r.path[0] != '/')
		return bad("run request (the program's path is not absolute)");
	if (r.cwd.empty() || r.cwd[0] != '/')
		return bad("run request (the working directory is not absolute)");
	if (r.argv.empty())
		return bad("run request (no argv[0])");
	if (!clean(r.path) || !clean(r.cwd))
		return bad("run request (a NUL inside a path)");
	for (const auto &s : r.argv)
		if (!clean(s))
			return bad("run request (a NUL inside an argument)");
	for (const auto &s : r.env) {
		if (!clean(s))
			return bad("run request (a NUL inside an environment entry)");
		if (s.find('=') == std::string::npos)
			return bad("run request (an environment entry without '=')");
	}
	if (!(r.cpu_scale == 0 || (std::isfinite(r.cpu_scale) && r.cpu_scale > 0)))
		return bad("run request (the CPU scale)");
	return r;
}

std::string encode_started(const StartedReply &r)
{
	return Writer().put(r.id).put(r.pid).put(r.mode).put(r.fifo_cpu).put(r.v_start).out;
}

Result<StartedReply> decode_started(std::string_view payload)
{
	Reader rd(payload);
	StartedReply r;
	r.id = rd.get<int32_t>();
	r.pid = rd.get<int32_t>();
	r.mode = rd.get<int32_t>();
	r.fifo_cpu = rd.get<int32_t>();
	r.v_start = rd.get<int64_t>();
	if (!rd.done())
		return bad("started reply");
	return r;
}

std::string encode_ended(const EndedReply &r)
{
	Writer w;
	w.put(r.wait_status).put(r.flags).put(r.v_end).put(r.charged_ns);
	w.put(r.waits).put(r.periodic_waits).put(r.deadline_misses).put(r.preemptions).str(r.dropped);
	return w.out;
}

Result<EndedReply> decode_ended(std::string_view payload)
{
	Reader rd(payload);
	EndedReply r;
	r.wait_status = rd.get<int32_t>();
	r.flags = rd.get<uint32_t>();
	r.v_end = rd.get<int64_t>();
	r.charged_ns = rd.get<int64_t>();
	r.waits = rd.get<uint64_t>();
	r.periodic_waits = rd.get<uint64_t>();
	r.deadline_misses = rd.get<uint64_t>();
	r.preemptions = rd.get<uint64_t>();
	r.dropped = rd.str();
	if (!rd.done())
		return bad("ended reply");
	return r;
}

std::string encode_signal(int32_t signo)
{
	return Writer().put(signo).out;
}

Result<int32_t> decode_signal(std::string_view payload)
{
	Reader rd(payload);
	int32_t signo = rd.get<int32_t>();
	if (!rd.done() || signo < 1 || signo > 64)
		return bad("signal request");
	return signo;
}

} // namespace tcs
