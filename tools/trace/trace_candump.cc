// tcs-trace export --format candump: a trace's CAN frames (the /tcs/wire/
// topics of CAN interfaces, trace/trace_wires.cc) as candump's log format,
// the lines `candump -L` prints and canplayer and can-utils' log tools read:
// "(SECONDS.MICROSECONDS) IFACE ID#DATA", stamped as a receiving socket's
// SO_TIMESTAMP is under tcs-run (the run's CLOCK_REALTIME origin plus the
// frame's end on the wire).
#include "trace_candump.h"

#include <algorithm>
#include <cinttypes>
#include <cstdlib>
#include <vector>

#include "json.h"
#include "message_decode.h"

namespace tcs {

namespace {

constexpr uint32_t kEff = 0x80000000u, kRtr = 0x40000000u, kErr = 0x20000000u;

struct Line {
	int64_t at; // CLOCK_REALTIME ns
	std::string iface, frame;
};

// A frame as can-utils' lib.c writes it with no separators: the id (3 hex
// digits, or 8 for an extended or error frame), '#', then for CAN FD a
// second '#' and the flags' digit, then the data; a remote frame 'R' and
// its length's digit when not 0.
std::string frame_text(uint32_t can_id, unsigned len, bool fd, unsigned flags, const JsonValue &data)
{
	char buf[16];
	if (can_id & (kEff | kErr))
		snprintf(buf, sizeof buf, "%08" PRIX32, can_id & ((can_id & kErr) ? 0x3fffffffu : 0x1fffffffu));
	else
		snprintf(buf, sizeof buf, "%03" PRIX32, can_id & 0x7ffu);
	std::string out = buf;
	out += '#';
	if (fd) {
		snprintf(buf, sizeof buf, "#%X", flags & 0xf);
		out += buf;
	} else if (can_id & kRtr) {
		out += 'R';
		if (len > 0 && len <= 8)
			out += "0123456789ABCDEF"[len];
		return out;
	}
	for (const JsonValue &b : data.array) {
		snprintf(buf, sizeof buf, "%02X", unsigned(b.integer & 0xff));
		out += buf;
	}
	return out;
}

} // namespace

Status export_candump(const std::string &path, const std::string &topic, FILE *out)
{
	std::vector<Line> lines;
	std::vector<std::string> buses;
	bool topic_seen = false;
	MessageDecoder decoder;
	auto s = for_each_message(path, [&](const McapMessage &m) -> Status {
		const McapChannel &c = *m.channel;
		auto kind = c.metadata.find("wire");
		if (kind == c.metadata.end() || kind->second != "can")
			return Ok{};
		auto name = c.metadata.find("name");
		const std::string iface = name != c.metadata.end() ? name->second : c.topic;
		if (std::find(buses.begin(), buses.end(), c.topic) == buses.end())
			buses.push_back(c.topic);
		if (!topic.empty() && c.topic != topic)
			return Ok{};
		topic_seen = true;
		auto where = [&] { return path + ": " + c.topic + " message " + std::to_string(m.sequence) + ": "; };
		auto v = decoder.decode(m);
		if (!v)
			return Error{ where() + v.error().message };
		const JsonValue *end = v->get("v_end_ns"), *id = v->get("can_id"), *len = v->get("len"),
				*fd = v->get("fd"), *flags = v->get("fd_flags"), *data = v->get("data");
		if (!end || !end->is_integer || !id || !id->is_integer || !len || !len->is_integer || !fd ||
		    fd->type != JsonValue::Type::Bool || !flags || !flags->is_integer || !data ||
		    data->type != JsonValue::Type::Array)
			return Error{ where() + "not a CAN frame as tcs writes it" };
		auto origin = c.metadata.find("realtime_origin_ns");
		const int64_t at = (origin != c.metadata.end() ? std::strtoll(origin->second.c_str(), nullptr, 10) : 0) +
				   end->integer;
		lines.push_back(Line{ at, iface,
				      frame_text(uint32_t(id->integer), unsigned(len->integer), fd->boolean,
						 unsigned(flags->integer), *data) });
		return Ok{};
	});
	if (!s)
		return s;
	if (!topic.empty() && !topic_seen) {
		std::string known;
		for (const std::string &b : buses)
			known += (known.empty() ? "" : ", ") + b;
		return Error{ path + ": " + topic + " is not a CAN bus of the trace" +
			      (known.empty() ? std::string(" (it has none)") : " (its: " + known + ")") };
	}
	if (buses.empty())
		return Error{ path + ": no CAN bus in the trace (a scenario's [[can]] traced with tcs-run --trace)" };
	// In time order across the buses, as one candump of them all prints,
	// the names padded to the longest as candump pads them.
	std::stable_sort(lines.begin(), lines.end(), [](const Line &a, const Line &b) { return a.at < b.at; });
	size_t width = 0;
	for (const Line &l : lines)
		width = std::max(width, l.iface.size());
	for (const Line &l : lines) {
		const int64_t sec = l.at / 1000000000, usec = (l.at % 1000000000) / 1000;
		fprintf(out, "(%010" PRId64 ".%06" PRId64 ") %*s %s\n", sec, usec, int(width), l.iface.c_str(),
			l.frame.c_str());
	}
	return Ok{};
}

} // namespace tcs
