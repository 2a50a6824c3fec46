// Records (record.h): the settings' JSON, and reading a record back.
#include "record.h"

#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdlib>

#include "json.h"
#include "mcap_reader.h"
#include "message_decode.h"

namespace tcs {

namespace {
// A journal's entries at most (a controller is untrusted, and so is a file):
// 2^28 entries are 4 GiB of replay table.
constexpr size_t kMostEntries = size_t(1) << 28;
} // namespace

std::string record_run_json(const Record &r)
{
	char buf[512];
	snprintf(buf, sizeof buf,
		 "{\"cpu_scale\":%.17g,\"step_ns\":%" PRId64 ",\"mono_origin_ns\":%" PRId64 ",\"real_origin_ns\":%" PRId64
		 ",\"tai_origin_ns\":%" PRId64 ",\"seed\":\"%" PRIu64 "\",\"sensor_key\":\"%" PRIu64
		 "\",\"slack\":%s,\"duration_ns\":%" PRId64 ",\"program\":[",
		 r.cpu_scale, r.step_ns, r.mono_origin_ns, r.real_origin_ns, r.tai_origin_ns, r.seed ? *r.seed : 0,
		 r.sensor_key, r.slack ? "true" : "false", r.duration_ns);
	std::string s = buf;
	auto strings = [&s](const std::vector<std::string> &v) {
		for (size_t i = 0; i < v.size(); i++) {
			if (i)
				s += ',';
			json_append_string(s, v[i]);
		}
	};
	strings(r.program);
	s += "],\"devices\":[";
	strings(r.devices);
	return s + "]}";
}

static Status take_settings(const std::string &path, const JsonValue &j, Record *r)
{
	r->cpu_scale = j.get_number("cpu_scale", 1.0);
	r->step_ns = j.get_int("step_ns");
	r->mono_origin_ns = j.get_int("mono_origin_ns");
	r->real_origin_ns = j.get_int("real_origin_ns");
	r->tai_origin_ns = j.get_int("tai_origin_ns");
	// (Strings: a seed takes all 64 bits, JSON's integers 63. Absent or 0:
	// none.)
	auto whole = [&](const char *key, uint64_t *out) -> Status {
		std::string text(j.get_string(key));
		char *end = nullptr;
		errno = 0;
		unsigned long long v = text.empty() ? 0 : strtoull(text.c_str(), &end, 10);
		if (!text.empty() && (errno || *end || text[0] == '-'))
			return Error{ path + ": the record's " + key + " is not a whole number" };
		*out = v;
		return Ok{};
	};
	uint64_t seed = 0;
	if (Status s = whole("seed", &seed); !s)
		return s;
	if (seed != 0)
		r->seed = seed;
	if (Status s = whole("sensor_key", &r->sensor_key); !s)
		return s;
	r->slack = j.get_bool("slack", true);
	r->duration_ns = j.get_int("duration_ns", -1); // (a record of an older tcs: none)
	if (r->duration_ns == 0 || r->duration_ns < -1)
		return Error{ path + ": the record's duration_ns is not valid" };
	if (!(r->cpu_scale > 0) || r->step_ns <= 0)
		return Error{ path + ": the record's settings are not valid (cpu_scale, step_ns)" };
	if (const JsonValue *p = j.get("program"); p && p->type == JsonValue::Type::Array)
		for (const JsonValue &a : p->array)
			r->program.push_back(a.string);
	if (const JsonValue *d = j.get("devices"); d && d->type == JsonValue::Type::Array)
		for (const JsonValue &a : d->array)
			r->devices.push_back(a.string);
	return Ok{};
}

static Status take_journal(const std::string &path, const JsonValue &j, Record *r)
{
	const JsonValue *entries = j.get("entries");
	int64_t controller = j.get_int("controller", -1);
	if (controller < 1 || controller > 1 << 20 || !entries || entries->type != JsonValue::Type::Array)
		return Error{ path + ": a journal message without its controller or entries" };
	std::vector<tcs_journal_entry> &out = r->journals[(int)controller];
	for (const JsonValue &e : entries->array) {
		// {kind, type, thread, value, arg} (CDR), or [kind, type, thread,
		// value, arg] (a JSON record of an older tcs).
		static const char *const names[] = { "kind", "type", "thread", "value", "arg" };
		const JsonValue *f[5] = {};
		for (size_t i = 0; i < 5; i++)
			f[i] = e.type == JsonValue::Type::Array ? (i < e.array.size() ? &e.array[i] : nullptr) : e.get(names[i]);
		bool ok = e.type != JsonValue::Type::Array || e.array.size() == 5;
		for (size_t i = 0; ok && i < 5; i++)
			ok = f[i] && f[i]->is_integer;
		if (!ok || f[0]->integer < 1 || f[0]->integer >= TCS_J_KINDS || f[1]->integer < 0 || f[1]->integer > 0xffff ||
		    f[2]->integer < 0 || f[2]->integer > 0xffffffffLL)
			return Error{ path + ": a journal entry that is not {kind, type, thread, value, arg}" };
		if (out.size() == kMostEntries)
			return Error{ path + ": more journal entries than a replay takes" };
		tcs_journal_entry x = {};
		x.kind = (uint16_t)f[0]->integer;
		x.type = (uint16_t)f[1]->integer;
		x.thread = (uint32_t)f[2]->integer;
		x.value = f[3]->integer;
		x.arg = f[4]->integer;
		out.push_back(x);
	}
	return Ok{};
}

static Status take_command(const std::string &path, const JsonValue &j, Record *r)
{
	int64_t controller = j.get_int("controller", -1);
	const JsonValue *values = j.get("values");
	if (controller < 1 || controller > 1 << 20 || !values || values->type != JsonValue::Type::Array)
		return Error{ path + ": a command without its controller or values" };
	auto &out = r->commands[(int)controller];
	if (out.size() == kMostEntries)
		return Error{ path + ": more commands than a replay takes" };
	RecordedCommand c;
	c.path = std::string(j.get_string("path"));
	c.v = j.get_int("v_ns");
	c.malformed = j.get_bool("malformed");
	for (const JsonValue &v : values->array)
		c.values.push_back(v.number);
	out.push_back(std::move(c));
	return Ok{};
}

static Status take_controller(const std::string &path, const JsonValue &j, Record *r)
{
	int64_t controller = j.get_int("controller", -1);
	double scale = j.get_number("cpu_scale", 0);
	if (controller < 1 || controller > 1 << 20 || !(scale > 0) || !std::isfinite(scale))
		return Error{ path + ": a controller without its number or CPU scale" };
	r->scales[(int)controller] = scale;
	return Ok{};
}

static Result<Record> read_from(McapReader &reader, const std::string &path)
{
	Record r;
	bool settings = false;
	MessageDecoder decoder;
	auto take = [&](const McapMessage &m) -> Status {
		const std::string &topic = m.channel->topic;
		static const struct {
			const char *topic;
			Status (*take)(const std::string &, const JsonValue &, Record *);
		} takers[] = { { "/tcs/record/run", take_settings }, { "/tcs/record/journal", take_journal },
			       { "/tcs/device", take_command }, { "/tcs/controller", take_controller } };
		for (const auto &t : takers) {
			if (topic != t.topic)
				continue;
			auto j = decoder.decode(m);
			if (!j)
				return Error{ path + ": " + topic + ": " + j.error().message };
			settings = settings || t.take == take_settings;
			return t.take(path, *j, &r);
		}
		return Ok{};
	};
	if (auto s = for_each_message(reader, take, &r.truncated); !s)
		return s.error();
	if (!settings)
		return Error{ path + ": not a record (a trace written without --record)" };
	return r;
}

Result<Record> read_record(const std::string &path)
{
	McapReader reader;
	if (auto s = reader.open(path); !s)
		return s.error();
	return read_from(reader, path);
}

Result<Record> read_record_bytes(std::string name, std::string bytes)
{
	McapReader reader;
	std::string path = name;
	if (auto s = reader.open_bytes(std::move(name), std::move(bytes)); !s)
		return s.error();
	return read_from(reader, path);
}

} // namespace tcs
