// Trace: the topics, their JSON Schemas, and JSON written without
// allocation on the per-message path (one reused buffer).
#include "trace.h"

#include <algorithm>
#include <charconv>
#include <initializer_list>
#include <utility>
#include <cinttypes>
#include <cstdarg>
#include <cmath>
#include <cstdio>

#include <sched.h>

namespace tcs {

namespace {

const char kControllerSchema[] = R"({"type":"object","title":"tcs controller","properties":{
"controller":{"type":"integer"},"name":{"type":"string"},"pid":{"type":"integer"},
"cpu_scale":{"type":"number"},"mode":{"type":"string","enum":["cpu","lockstep"]},
"step_ns":{"type":"integer"}}})";

const char kSliceSchema[] = R"({"type":"object","title":"tcs slice","properties":{
"controller":{"type":"integer"},"v_start_ns":{"type":"integer"},"v_end_ns":{"type":"integer"},
"charged_ns":{"type":"integer","description":"virtual CPU charged"},
"cpu_ns":{"type":"integer","description":"real CPU the process used, tcs hooks included"},
"wall_start_ns":{"type":"integer"},"wall_end_ns":{"type":"integer"},
"budget_ns":{"type":"integer","description":"preempted: the real CPU budget; else -1"},
"overshoot_ns":{"type":"integer","description":"preempted: real CPU used beyond the budget"},
"sim_ns":{"type":"integer","description":"simulation time when the slice ended"},
"end":{"type":"string","enum":["blocked","preempted","exited","ended"],
"description":"ended: the run ended while it ran"}}})";

const char kWaitSchema[] = R"({"type":"object","title":"tcs wait","properties":{
"controller":{"type":"integer"},"kind":{"type":"string"},"v_request_ns":{"type":"integer"},
"deadline_ns":{"type":"integer","description":"-1: none"},"v_end_ns":{"type":"integer"},
"absolute":{"type":"boolean"}}})";

const char kDeviceSchema[] = R"({"type":"object","title":"tcs actuator command","properties":{
"controller":{"type":"integer"},"path":{"type":"string"},"v_ns":{"type":"integer"},
"values":{"type":"array","items":{"type":"number"}},"malformed":{"type":"boolean"}}})";

const char kStepSchema[] = R"({"type":"object","title":"tcs simulation step","properties":{
"v_ns":{"type":"integer"},"wall_ns":{"type":"integer","description":"wall time since the run started"},
"wall_cost_ns":{"type":"integer"},
"joints":{"type":"object","additionalProperties":{"type":"number"}}}})";

// As ROS 2's rosgraph_msgs/Clock, so tools that follow /clock follow tcs.
const char kClockSchema[] = R"({"type":"object","title":"rosgraph_msgs/Clock","properties":{
"clock":{"type":"object","properties":{"sec":{"type":"integer"},"nanosec":{"type":"integer"}}}}})";

// A record's (trace/record.h).
const char kRecordRunSchema[] = R"({"type":"object","title":"tcs record: the run's settings","properties":{
"cpu_scale":{"type":"number"},"step_ns":{"type":"integer"},"mono_origin_ns":{"type":"integer"},
"real_origin_ns":{"type":"integer"},"tai_origin_ns":{"type":"integer"},"seed":{"type":"string","description":"--seed in decimal, 0 for none"},
"slack":{"type":"boolean"},"program":{"type":"array","items":{"type":"string"}},
"devices":{"type":"array","items":{"type":"string"}}}})";

const char kJournalSchema[] = R"json({"type":"object","title":"tcs record: a controller's journal","properties":{
"controller":{"type":"integer"},"entries":{"type":"array","description":"[kind, type, thread, value, arg]: kind 1 clock read (value: virtual ns), 2 CPU-time clock, 3 thread CPU-time clock, 4 request (type: its message type; value: virtual ns), 5 device read (value: virtual ns; arg: bytes read), 6 the coordinator's preemption (value: virtual ns; arg: real CPU past its budget), 7 the process's end (value: virtual ns)",
"items":{"type":"array","items":{"type":"integer"}}}}})json";

void append(std::string &s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void append(std::string &s, const char *fmt, ...)
{
	char buf[512];
	va_list ap;
	va_start(ap, fmt);
	int n = vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	if (n > 0)
		s.append(buf, (size_t)std::min(n, (int)sizeof buf - 1));
}

// A JSON string: the paths and names tcs writes are plain, but quote and
// escape them properly all the same.
void append_string(std::string &s, const std::string &v)
{
	s += '"';
	for (char c : v) {
		if (c == '"' || c == '\\')
			s += '\\';
		if ((unsigned char)c < 0x20)
			append(s, "\\u%04x", c);
		else
			s += c;
	}
	s += '"';
}

// Numbers: to_chars, not printf (a 1 kHz run writes five messages and a
// dozen numbers a cycle, and the writer thread shares a busy core). A
// double is written in the shortest form that reads back the same.
void append_int(std::string &s, int64_t v)
{
	char buf[24];
	s.append(buf, (size_t)(std::to_chars(buf, buf + sizeof buf, v).ptr - buf));
}

void append_number(std::string &s, double v)
{
	if (!std::isfinite(v)) {
		s += "null";
		return;
	}
	char buf[32];
	s.append(buf, (size_t)(std::to_chars(buf, buf + sizeof buf, v).ptr - buf));
}

// ,"key":v for each (key, v): the keys written with their quotes.
void append_fields(std::string &s, std::initializer_list<std::pair<const char *, int64_t>> fields)
{
	for (const auto &[key, v] : fields) {
		s += key;
		append_int(s, v);
	}
}

} // namespace

Status Trace::open(const std::string &path, TraceWriting how, bool record)
{
	if (auto s = writer_.open(path, "", "tcs"); !s)
		return s;
	struct Topic {
		const char *topic, *schema_name, *schema;
		uint16_t *id;
	} topics[] = {
		{ "/tcs/controller", "tcs.Controller", kControllerSchema, &controller_ },
		{ "/tcs/slice", "tcs.Slice", kSliceSchema, &slice_ },
		{ "/tcs/wait", "tcs.Wait", kWaitSchema, &wait_ },
		{ "/tcs/device", "tcs.Command", kDeviceSchema, &device_ },
		{ "/tcs/step", "tcs.Step", kStepSchema, &step_ },
		{ "/clock", "rosgraph_msgs/Clock", kClockSchema, &clock_ },
		{ "/tcs/record/run", "tcs.RecordRun", kRecordRunSchema, &record_run_ },
		{ "/tcs/record/journal", "tcs.Journal", kJournalSchema, &journal_ },
	};
	for (const auto &t : topics) {
		if (!record && (t.id == &record_run_ || t.id == &journal_))
			continue;
		auto schema = writer_.add_schema(t.schema_name, t.schema);
		if (!schema)
			return schema.error();
		auto channel = writer_.add_channel(t.topic, *schema);
		if (!channel)
			return channel.error();
		*t.id = *channel;
	}
	json_.reserve(4096);
	open_ = true;
	pumped_ = how.pumped;
	if (!pumped_)
		thread_ = std::thread([this, avoid = how.avoid_cpu] { writer_loop(avoid); });
	return Ok{};
}

Status Trace::close()
{
	if (!open_)
		return Ok{};
	if (pumped_) {
		while (!pending_.empty())
			write_oldest();
	} else {
		{
			std::lock_guard<std::mutex> lk(mu_);
			stop_ = true;
		}
		cv_.notify_one();
		thread_.join();
	}
	open_ = false;
	auto s = writer_.close();
	return status_ ? s : status_;
}

// Past this many messages waiting, the coordinator writes as it emits: a
// run that never leaves it idle (a world stepped back to back) keeps its
// trace's memory bounded all the same.
constexpr size_t kMostPending = 8192;

void Trace::emit(Event &&e)
{
	if (pumped_) {
		pending_.push_back(std::move(e));
		if (pending_.size() > kMostPending) {
			write_oldest();
			write_oldest();
		}
		return;
	}
	{
		std::lock_guard<std::mutex> lk(mu_);
		queue_.push_back(std::move(e));
		if (queue_.size() < 1024)
			return;
	}
	cv_.notify_one();
}

void Trace::write_oldest()
{
	if (status_)
		write_event(pending_.front());
	pending_.pop_front();
}

bool Trace::pump()
{
	if (pending_.empty())
		return false;
	write_oldest();
	return true;
}

void Trace::writer_loop(int avoid_cpu)
{
	// Normal priority, on the other cores: the coordinator's SCHED_FIFO
	// and its one core are the run's.
	struct sched_param sp = {};
	sched_setscheduler(0, SCHED_OTHER, &sp);
	cpu_set_t set;
	if (avoid_cpu >= 0 && sched_getaffinity(0, sizeof set, &set) == 0) {
		cpu_set_t all;
		CPU_ZERO(&all);
		for (int c = 0; c < CPU_SETSIZE; c++)
			CPU_SET(c, &all);
		CPU_CLR(avoid_cpu, &all);
		sched_setaffinity(0, sizeof all, &all); // fails harmlessly on one core
	}
	std::vector<Event> batch;
	for (;;) {
		{
			std::unique_lock<std::mutex> lk(mu_);
			// Written at least every 20 ms, so a killed run loses little.
			cv_.wait_for(lk, std::chrono::milliseconds(20), [this] { return stop_ || queue_.size() >= 1024; });
			batch.swap(queue_);
			if (stop_ && batch.empty())
				return;
		}
		for (const auto &e : batch)
			if (status_)
				write_event(e);
		batch.clear();
	}
}

void Trace::controller(int controller, const std::string &name, int pid, double cpu_scale, int mode,
			int64_t step_ns)
{
	Event e{ Event::ControllerInfo };
	e.controller = controller;
	e.path = &name;
	e.f[0] = pid;
	e.f[1] = step_ns;
	e.scale = cpu_scale;
	e.text = mode == 1 ? "lockstep" : "cpu";
	emit(std::move(e));
}

void Trace::slice(int controller, const Slice &s)
{
	Event e{ Event::SliceEnd };
	e.controller = controller;
	int64_t f[] = { s.v_start, s.v_end, s.charged_ns, s.cpu_ns, s.wall_start, s.wall_end, s.budget_ns,
			s.overshoot_ns, s.sim_ns };
	std::copy(std::begin(f), std::end(f), e.f);
	e.text = s.why;
	emit(std::move(e));
}

void Trace::wait(int controller, const char *kind, int64_t v_request, int64_t deadline, int64_t v_end, bool absolute)
{
	Event e{ Event::Wait };
	e.controller = controller;
	e.text = kind;
	e.f[0] = v_request;
	e.f[1] = deadline == INT64_MAX ? -1 : deadline;
	e.f[2] = v_end;
	e.flag = absolute;
	emit(std::move(e));
}

void Trace::command(int controller, const std::string &path, int64_t v, std::vector<double> values, bool malformed)
{
	Event e{ Event::Command };
	e.controller = controller;
	e.path = &path;
	e.f[0] = v;
	e.values = std::move(values);
	e.flag = malformed;
	emit(std::move(e));
}

void Trace::step(int64_t v, int64_t wall_ns, int64_t wall_cost_ns, std::vector<double> joint_values)
{
	Event e{ Event::Step };
	e.f[0] = v;
	e.f[1] = wall_ns;
	e.f[2] = wall_cost_ns;
	e.values = std::move(joint_values);
	emit(std::move(e));
}

void Trace::record_run(std::string json)
{
	Event e{ Event::RecordRun };
	e.json = std::move(json);
	emit(std::move(e));
}

void Trace::journal(int controller, std::vector<tcs_journal_entry> entries)
{
	if (entries.empty())
		return;
	Event e{ Event::Journal };
	e.controller = controller;
	e.entries = std::move(entries);
	emit(std::move(e));
}

void Trace::write_event(const Event &e)
{
	auto put = [this](uint16_t channel, int64_t v) {
		uint64_t t = v < 0 ? 0 : (uint64_t)v;
		if (auto s = writer_.write(channel, t, t, json_); !s)
			status_ = s;
	};
	json_.clear();
	switch (e.kind) {
	case Event::ControllerInfo:
		append(json_, "{\"controller\":%d,\"name\":", e.controller);
		append_string(json_, *e.path);
		append(json_, ",\"pid\":%" PRId64 ",\"cpu_scale\":", e.f[0]);
		append_number(json_, e.scale);
		append(json_, ",\"mode\":\"%s\",\"step_ns\":%" PRId64 "}", e.text, e.f[1]);
		put(controller_, 0);
		return;
	case Event::SliceEnd:
		append_fields(json_, { { "{\"controller\":", e.controller }, { ",\"v_start_ns\":", e.f[0] },
				       { ",\"v_end_ns\":", e.f[1] }, { ",\"charged_ns\":", e.f[2] }, { ",\"cpu_ns\":", e.f[3] },
				       { ",\"wall_start_ns\":", e.f[4] }, { ",\"wall_end_ns\":", e.f[5] },
				       { ",\"budget_ns\":", e.f[6] }, { ",\"overshoot_ns\":", e.f[7] }, { ",\"sim_ns\":", e.f[8] } });
		json_ += ",\"end\":\"";
		json_ += e.text;
		json_ += "\"}";
		put(slice_, e.f[0]);
		return;
	case Event::Wait:
		append_fields(json_, { { "{\"controller\":", e.controller } });
		json_ += ",\"kind\":\"";
		json_ += e.text;
		json_ += '"';
		append_fields(json_, { { ",\"v_request_ns\":", e.f[0] }, { ",\"deadline_ns\":", e.f[1] },
				       { ",\"v_end_ns\":", e.f[2] } });
		json_ += e.flag ? ",\"absolute\":true}" : ",\"absolute\":false}";
		put(wait_, e.f[0]);
		return;
	case Event::Command:
		append_fields(json_, { { "{\"controller\":", e.controller } });
		json_ += ",\"path\":";
		append_string(json_, *e.path);
		append_fields(json_, { { ",\"v_ns\":", e.f[0] } });
		json_ += ",\"values\":[";
		for (size_t i = 0; i < e.values.size(); i++) {
			if (i)
				json_ += ',';
			append_number(json_, e.values[i]);
		}
		json_ += e.flag ? "],\"malformed\":true}" : "],\"malformed\":false}";
		put(device_, e.f[0]);
		return;
	case Event::Step:
		append_fields(json_, { { "{\"v_ns\":", e.f[0] }, { ",\"wall_ns\":", e.f[1] }, { ",\"wall_cost_ns\":", e.f[2] } });
		json_ += ",\"joints\":{";
		for (size_t i = 0; i < e.values.size() && i < joint_names_.size(); i++) {
			if (i)
				json_ += ',';
			append_string(json_, joint_names_[i]);
			json_ += ':';
			append_number(json_, e.values[i]);
		}
		json_ += "}}";
		put(step_, e.f[0]);
		json_.clear();
		append_fields(json_, { { "{\"clock\":{\"sec\":", e.f[0] / 1000000000 }, { ",\"nanosec\":", e.f[0] % 1000000000 } });
		json_ += "}}";
		put(clock_, e.f[0]);
		return;
	case Event::RecordRun:
		json_ = e.json;
		put(record_run_, 0);
		return;
	case Event::Journal: {
		append(json_, "{\"controller\":%d,\"entries\":", e.controller);
		int64_t at = 0;
		json_ += '[';
		for (size_t i = 0; i < e.entries.size(); i++) {
			const tcs_journal_entry &j = e.entries[i];
			json_ += i ? ",[" : "[";
			const int64_t fields[] = { j.kind, j.type, j.thread, j.value, j.arg };
			for (size_t f = 0; f < 5; f++) {
				if (f)
					json_ += ',';
				append_int(json_, fields[f]);
			}
			json_ += ']';
			if (j.kind == TCS_J_CLOCK || j.kind == TCS_J_CHARGE || j.kind == TCS_J_READ)
				at = j.value;
		}
		json_ += "]}";
		put(journal_, at); // (logged at its last virtual time)
		return;
	}
	}
}

} // namespace tcs
