// Trace: the topics, their schemas, and their messages written without
// allocation on the per-message path (one reused buffer).
#include "trace.h"

#include "cdr_writer.h"
#include "json.h"

#include <algorithm>
#include <utility>

#include <sched.h>

namespace tcs {

namespace {

const char kControllerSchema[] = R"({"type":"object","title":"tcs controller","properties":{
"controller":{"type":"integer"},"name":{"type":"string"},"pid":{"type":"integer"},
"cpu_scale":{"type":"number"},"mode":{"type":"string","enum":["cpu","lockstep"]},
"step_ns":{"type":"integer"}}})";

// The per-cycle topics: ROS 2 message definitions (ros2msg) of CDR
// messages, which Foxglove and PlotJuggler decode, and which cost the
// coordinator a few stores each (JSON cost it more than the run's own
// work: docs/PERFORMANCE.md).
const char kSliceSchema[] = R"(# tcs: a stretch of virtual time a controller ran
int32 controller
int64 v_start_ns
int64 v_end_ns
int64 charged_ns # virtual CPU charged
int64 cpu_ns # real CPU the process used, tcs hooks included
int64 wall_start_ns
int64 wall_end_ns
int64 budget_ns # preempted: the real CPU budget; else -1
int64 overshoot_ns # preempted: real CPU used beyond the budget
int64 sim_ns # simulation time when the slice ended
string end # blocked, preempted, exited, or ended (the run ended while it ran)
)";

const char kWaitSchema[] = R"(# tcs: a hooked wait
int32 controller
string kind
int64 v_request_ns
int64 deadline_ns # -1: none
int64 v_end_ns
bool absolute
)";

const char kDeviceSchema[] = R"(# tcs: a command written to an actuator
int32 controller
string path
int64 v_ns
float64[] values
bool malformed
)";

const char kStepSchema[] = R"(# tcs: a simulation step and the joint states after it
int64 v_ns
int64 wall_ns # wall time since the run started
int64 wall_cost_ns
string[] joint_names
float64[] joint_values
)";

// As ROS 2's rosgraph_msgs/Clock, so tools that follow /clock follow tcs.
const char kClockSchema[] = R"(builtin_interfaces/Time clock
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
)";

// A record's (trace/record.h).
const char kRecordRunSchema[] = R"({"type":"object","title":"tcs record: the run's settings","properties":{
"cpu_scale":{"type":"number"},"step_ns":{"type":"integer"},"mono_origin_ns":{"type":"integer"},
"real_origin_ns":{"type":"integer"},"tai_origin_ns":{"type":"integer"},"seed":{"type":"string","description":"--seed in decimal, 0 for none"},
"slack":{"type":"boolean"},"duration_ns":{"type":"integer","description":"--duration; -1: until the programs ended"},
"program":{"type":"array","items":{"type":"string"}},
"devices":{"type":"array","items":{"type":"string"}}}})";

const char kJournalSchema[] = R"(# tcs record: a controller's journal
int32 controller
tcs_msgs/JournalEntry[] entries
================================================================================
MSG: tcs_msgs/JournalEntry
# kind 1 clock read (value: virtual ns), 2 CPU-time clock, 3 thread CPU-time
# clock, 4 request (type: its message type; value: virtual ns), 5 device read
# (value: virtual ns; arg: bytes read), 6 the coordinator's preemption
# (value: virtual ns; arg: real CPU past its budget), 7 the process's end
# (value: virtual ns)
uint16 kind
uint16 type
uint32 thread
int64 value
int64 arg
)";

} // namespace

Status Trace::open(const std::string &path, TraceWriting how, bool record)
{
	// Written by the coordinator, between its requests: uncompressed, as
	// compressing cost a 1 kHz run 15 to 25 % more wall time; a thread of
	// its own compresses off the coordinator's core (docs/PERFORMANCE.md).
	writer_.emplace(McapWriterOptions{ .compression = how.pumped ? McapCompression::none : McapCompression::zstd,
					   .zstd_level = 1 });
	if (auto s = writer_->open(path, "", "tcs"); !s)
		return s;
	// JSON for the messages written once, CDR for those written every cycle.
	constexpr bool json = true, cdr = false;
	struct Topic {
		const char *topic, *schema_name, *schema;
		bool json;
		uint16_t *id;
	} topics[] = {
		{ "/tcs/controller", "tcs.Controller", kControllerSchema, json, &controller_ },
		{ "/tcs/slice", "tcs_msgs/msg/Slice", kSliceSchema, cdr, &slice_ },
		{ "/tcs/wait", "tcs_msgs/msg/Wait", kWaitSchema, cdr, &wait_ },
		{ "/tcs/device", "tcs_msgs/msg/Command", kDeviceSchema, cdr, &device_ },
		{ "/tcs/step", "tcs_msgs/msg/Step", kStepSchema, cdr, &step_ },
		{ "/clock", "rosgraph_msgs/msg/Clock", kClockSchema, cdr, &clock_ },
		{ "/tcs/record/run", "tcs.RecordRun", kRecordRunSchema, json, &record_run_ },
		{ "/tcs/record/journal", "tcs_msgs/msg/Journal", kJournalSchema, cdr, &journal_ },
	};
	for (const auto &t : topics) {
		if (!record && (t.id == &record_run_ || t.id == &journal_))
			continue;
		auto schema = writer_->add_schema(t.schema_name, t.json ? "jsonschema" : "ros2msg", t.schema);
		if (!schema)
			return schema.error();
		auto channel = writer_->add_channel(t.topic, t.json ? "json" : "cdr", *schema);
		if (!channel)
			return channel.error();
		*t.id = *channel;
	}
	buf_.reserve(4096);
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
	auto s = writer_->close();
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
		if (auto s = writer_->write(channel, t, t, buf_); !s)
			status_ = s;
	};
	buf_.clear();
	switch (e.kind) {
	case Event::ControllerInfo: {
		JsonValue msg;
		msg.type = JsonValue::Type::Object;
		auto add = [&msg](const char *key, JsonValue x) { msg.object.emplace_back(key, std::move(x)); };
		add("controller", json_integer(e.controller));
		add("name", json_string(*e.path));
		add("pid", json_integer(e.f[0]));
		add("cpu_scale", json_number(e.scale));
		add("mode", json_string(e.text));
		add("step_ns", json_integer(e.f[1]));
		json_append(buf_, msg);
		put(controller_, 0);
		return;
	}
	case Event::SliceEnd: {
		CdrWriter w(buf_);
		w.put<int32_t>(e.controller);
		for (int64_t f : e.f)
			w.put<int64_t>(f);
		w.put_string(e.text);
		put(slice_, e.f[0]);
		return;
	}
	case Event::Wait: {
		CdrWriter w(buf_);
		w.put<int32_t>(e.controller);
		w.put_string(e.text);
		for (int i = 0; i < 3; i++)
			w.put<int64_t>(e.f[i]);
		w.put_bool(e.flag);
		put(wait_, e.f[0]);
		return;
	}
	case Event::Command: {
		CdrWriter w(buf_);
		w.put<int32_t>(e.controller);
		w.put_string(*e.path);
		w.put<int64_t>(e.f[0]);
		w.put_count(e.values.size());
		for (double v : e.values)
			w.put<double>(v);
		w.put_bool(e.flag);
		put(device_, e.f[0]);
		return;
	}
	case Event::Step: {
		const size_t n = std::min(e.values.size(), joint_names_.size());
		CdrWriter w(buf_);
		for (int i = 0; i < 3; i++)
			w.put<int64_t>(e.f[i]);
		w.put_count(n);
		for (size_t i = 0; i < n; i++)
			w.put_string(joint_names_[i]);
		w.put_count(n);
		for (size_t i = 0; i < n; i++)
			w.put<double>(e.values[i]);
		put(step_, e.f[0]);
		CdrWriter clock(buf_);
		clock.put<int32_t>((int32_t)(e.f[0] / 1000000000));
		clock.put<uint32_t>((uint32_t)(e.f[0] % 1000000000));
		put(clock_, e.f[0]);
		return;
	}
	case Event::RecordRun:
		buf_ = e.json;
		put(record_run_, 0);
		return;
	case Event::Journal: {
		CdrWriter w(buf_);
		w.put<int32_t>(e.controller);
		w.put_count(e.entries.size());
		int64_t at = 0;
		for (const tcs_journal_entry &j : e.entries) {
			w.put<uint16_t>(j.kind);
			w.put<uint16_t>(j.type);
			w.put<uint32_t>(j.thread);
			w.put<int64_t>(j.value);
			w.put<int64_t>(j.arg);
			if (j.kind == TCS_J_CLOCK || j.kind == TCS_J_CHARGE || j.kind == TCS_J_READ)
				at = j.value;
		}
		put(journal_, at); // (logged at its last virtual time)
		return;
	}
	}
}

} // namespace tcs
