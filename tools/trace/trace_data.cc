// load_trace: MCAP messages (JSON or CDR) → typed records, checking each
// field.
#include "trace_data.h"

#include <algorithm>
#include <map>

#include "json.h"
#include "message_decode.h"

namespace tcs {

namespace {

// Reads the fields of one message; the first missing or mistyped one
// makes an error naming it.
class Fields {
public:
	explicit Fields(const JsonValue &v) : v_(v) {}
	int64_t integer(const char *key)
	{
		const JsonValue *f = v_.get(key);
		if (!f || !f->is_integer)
			return missing(key, "an integer");
		return f->integer;
	}
	double number(const char *key)
	{
		const JsonValue *f = v_.get(key);
		if (!f || f->type != JsonValue::Type::Number)
			return missing(key, "a number");
		return f->number;
	}
	std::string string(const char *key)
	{
		const JsonValue *f = v_.get(key);
		if (!f || f->type != JsonValue::Type::String)
			return missing(key, "a string"), "";
		return f->string;
	}
	bool boolean(const char *key)
	{
		const JsonValue *f = v_.get(key);
		if (!f || f->type != JsonValue::Type::Bool)
			return missing(key, "true or false");
		return f->boolean;
	}
	const JsonValue &member(const char *key, JsonValue::Type type, const char *what)
	{
		static const JsonValue none;
		const JsonValue *f = v_.get(key);
		if (!f || f->type != type)
			return missing(key, what), none;
		return *f;
	}
	const std::string &problem() const { return problem_; }

private:
	int missing(const char *key, const char *what)
	{
		if (problem_.empty())
			problem_ = std::string("\"") + key + "\" is not " + what;
		return 0;
	}
	const JsonValue &v_;
	std::string problem_;
};

std::vector<double> numbers(const JsonValue &array, std::string *problem)
{
	std::vector<double> out;
	for (const auto &x : array.array) {
		// JSON has no NaN: the writer puts null for a value that is not finite.
		if (x.type == JsonValue::Type::Number)
			out.push_back(x.number);
		else if (x.type == JsonValue::Type::Null)
			out.push_back(__builtin_nan(""));
		else if (problem->empty())
			*problem = "a value is not a number";
	}
	return out;
}

Status parse_message(TraceData &t, std::string_view topic, const JsonValue &msg)
{
	Fields f(msg);
	std::string extra;
	if (topic == "/tcs/controller") {
		TraceController c;
		c.id = (int)f.integer("controller");
		c.name = f.string("name");
		c.pid = f.integer("pid");
		c.cpu_scale = f.number("cpu_scale");
		c.mode = f.string("mode");
		c.step_ns = f.integer("step_ns");
		if (f.problem().empty() && (c.mode != "cpu" && c.mode != "lockstep"))
			extra = "unknown mode \"" + c.mode + "\"";
		// Described again with the same pid: a child that exec'd another
		// program, named by it from then on.
		auto same = std::find_if(t.controllers.begin(), t.controllers.end(),
					 [&](const TraceController &x) { return x.id == c.id; });
		if (f.problem().empty() && extra.empty() && same != t.controllers.end()) {
			if (same->pid != c.pid)
				extra = "controller " + std::to_string(c.id) + " described twice";
			else
				*same = std::move(c);
		} else {
			t.controllers.push_back(std::move(c));
		}
	} else if (topic == "/tcs/slice") {
		TraceSlice s;
		s.controller = (int)f.integer("controller");
		s.v_start = f.integer("v_start_ns");
		s.v_end = f.integer("v_end_ns");
		s.charged = f.integer("charged_ns");
		s.cpu = f.integer("cpu_ns");
		s.wall_start = f.integer("wall_start_ns");
		s.wall_end = f.integer("wall_end_ns");
		s.budget = f.integer("budget_ns");
		s.overshoot = f.integer("overshoot_ns");
		s.sim = f.integer("sim_ns");
		std::string end = f.string("end");
		if (end == "blocked")
			s.end = TraceSlice::End::Blocked;
		else if (end == "preempted")
			s.end = TraceSlice::End::Preempted;
		else if (end == "exited")
			s.end = TraceSlice::End::Exited;
		else if (end == "ended")
			s.end = TraceSlice::End::Ended;
		else if (f.problem().empty())
			extra = "unknown end \"" + end + "\"";
		t.slices.push_back(s);
	} else if (topic == "/tcs/wait") {
		TraceWait w;
		w.controller = (int)f.integer("controller");
		w.kind = f.string("kind");
		w.v_request = f.integer("v_request_ns");
		w.deadline = f.integer("deadline_ns");
		w.v_end = f.integer("v_end_ns");
		w.absolute = f.boolean("absolute");
		t.waits.push_back(std::move(w));
	} else if (topic == "/tcs/device") {
		TraceCommand c;
		c.controller = (int)f.integer("controller");
		c.path = f.string("path");
		c.v = f.integer("v_ns");
		c.values = numbers(f.member("values", JsonValue::Type::Array, "an array"), &extra);
		c.malformed = f.boolean("malformed");
		t.commands.push_back(std::move(c));
	} else if (topic == "/tcs/step") {
		TraceStep s;
		s.v = f.integer("v_ns");
		s.wall = f.integer("wall_ns");
		s.wall_cost = f.integer("wall_cost_ns");
		// joint_names and joint_values (a JSON trace of an older tcs: a
		// "joints" object of them)
		std::vector<std::pair<std::string, const JsonValue *>> joints;
		if (const JsonValue *o = msg.get("joints"); o && o->type == JsonValue::Type::Object) {
			for (const auto &[name, value] : o->object)
				joints.emplace_back(name, &value);
		} else {
			const JsonValue &names = f.member("joint_names", JsonValue::Type::Array, "an array");
			const JsonValue &values = f.member("joint_values", JsonValue::Type::Array, "an array");
			if (names.array.size() != values.array.size() && f.problem().empty())
				extra = "joint_names and joint_values differ in length";
			for (size_t i = 0; i < names.array.size() && i < values.array.size(); i++)
				joints.emplace_back(names.array[i].string, &values.array[i]);
		}
		if (t.steps.empty())
			for (const auto &[name, value] : joints)
				t.joint_names.push_back(name);
		// Every step names the same joints in the same order.
		for (size_t i = 0; i < joints.size() && extra.empty(); i++) {
			const auto &[name, value] = joints[i];
			if (i >= t.joint_names.size() || name != t.joint_names[i])
				extra = "joint \"" + name + "\" not in the first step's list";
			else if (value->type == JsonValue::Type::Number)
				s.joints.push_back(value->number);
			else if (value->type == JsonValue::Type::Null)
				s.joints.push_back(__builtin_nan(""));
			else
				extra = "joint \"" + name + "\" is not a number";
		}
		if (extra.empty() && s.joints.size() != t.joint_names.size())
			extra = "not every joint has a value";
		t.steps.push_back(std::move(s));
	}
	if (!f.problem().empty())
		return Error{ f.problem() };
	if (!extra.empty())
		return Error{ extra };
	return Ok{};
}

// A message of a wire's topic: counted into its TraceWire.
Status count_wire(TraceWire &w, const JsonValue &msg)
{
	Fields f(msg);
	const int64_t start = f.integer("v_start_ns"), end = f.integer("v_end_ns");
	const std::string from = f.string("from"), note = f.string("note");
	uint64_t bytes = 0;
	bool failed = false;
	if (w.kind == "i2c") {
		failed = f.integer("result") < 0;
		for (const JsonValue &m : f.member("messages", JsonValue::Type::Array, "an array").array)
			if (const JsonValue *d = m.get("data"); d && d->type == JsonValue::Type::Array)
				bytes += d->array.size();
	} else {
		bytes = f.member("data", JsonValue::Type::Array, "an array").array.size();
	}
	if (!f.problem().empty())
		return Error{ f.problem() };
	if (end < start)
		return Error{ "it ends before it starts" };
	if (!note.empty() || failed)
		w.refused++;
	if (w.kind == "serial" && bytes == 0)
		return Ok{}; // (a note alone)
	w.messages++;
	w.bytes += bytes;
	(w.kind == "serial" && from.rfind("servo ", 0) == 0 ? w.busy_back_ns : w.busy_ns) += end - start;
	return Ok{};
}

} // namespace

const TraceController *TraceData::controller(int id) const
{
	for (const auto &c : controllers)
		if (c.id == id)
			return &c;
	return nullptr;
}

int64_t TraceData::virtual_ns() const
{
	int64_t v = 0;
	for (const auto &s : slices)
		v = std::max(v, s.v_end);
	for (const auto &w : waits)
		v = std::max(v, w.v_end);
	if (!steps.empty())
		v = std::max(v, steps.back().v);
	return v;
}

int64_t TraceData::wall_ns() const
{
	int64_t w = 0;
	for (const auto &s : slices)
		w = std::max(w, s.wall_end);
	if (!steps.empty())
		w = std::max(w, steps.back().wall);
	return w;
}

Result<TraceData> load_trace(const std::string &path)
{
	TraceData t;
	t.path = path;
	std::map<std::string, uint64_t> counts;
	MessageDecoder decoder;
	auto read = for_each_message(
		path,
		[&](const McapMessage &m) -> Status {
			const std::string &topic = m.channel->topic;
			uint64_t n = counts[topic]++;
			t.messages++;
			if (topic.rfind("/tcs/", 0) != 0)
				return Ok{}; // /clock, or someone else's topic: not needed here
			auto where = [&] { return path + ": " + topic + " message " + std::to_string(n + 1) + ": "; };
			auto v = decoder.decode(m);
			if (!v)
				return Error{ where() + v.error().message };
			if (v->type != JsonValue::Type::Object)
				return Error{ where() + "not a JSON object" };
			if (auto kind = m.channel->metadata.find("wire"); kind != m.channel->metadata.end()) {
				auto w = std::find_if(t.wires.begin(), t.wires.end(),
						      [&](const TraceWire &x) { return x.topic == topic; });
				if (w == t.wires.end()) {
					auto name = m.channel->metadata.find("name");
					t.wires.push_back(TraceWire{ .topic = topic,
								     .kind = kind->second,
								     .name = name != m.channel->metadata.end() ? name->second
													: topic });
					w = t.wires.end() - 1;
				}
				if (auto st = count_wire(*w, *v); !st)
					return Error{ where() + st.error().message };
				return Ok{};
			}
			if (auto st = parse_message(t, topic, *v); !st)
				return Error{ where() + st.error().message };
			return Ok{};
		},
		&t.truncated);
	if (!read)
		return read.error();
	if (!counts.count("/tcs/controller") && !counts.count("/tcs/slice"))
		return Error{ path + ": not a tcs trace (it has no /tcs/controller or /tcs/slice messages; "
				     "a trace from an older tcs lacks /tcs/controller: record it again)" };
	for (const auto &s : t.slices)
		if (!t.controller(s.controller))
			return Error{ path + ": /tcs/slice of controller " + std::to_string(s.controller) +
				      ", which no /tcs/controller message describes" };
	// Records are written in the order they happen; sort all the same, as
	// a merged or rewritten file need not be.
	std::stable_sort(t.controllers.begin(), t.controllers.end(),
			 [](const auto &a, const auto &b) { return a.id < b.id; });
	std::stable_sort(t.slices.begin(), t.slices.end(), [](const auto &a, const auto &b) {
		return a.controller != b.controller ? a.controller < b.controller : a.v_start < b.v_start;
	});
	std::stable_sort(t.waits.begin(), t.waits.end(), [](const auto &a, const auto &b) {
		return a.controller != b.controller ? a.controller < b.controller : a.v_request < b.v_request;
	});
	std::stable_sort(t.steps.begin(), t.steps.end(), [](const auto &a, const auto &b) { return a.v < b.v; });
	return t;
}

} // namespace tcs
