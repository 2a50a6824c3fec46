// Trace: the topics, their schemas, and their messages, encoded without
// allocation on the per-message path (one reused buffer) and written by the
// caller or by a thread of the trace's own.
#include "trace.h"

#include "cdr_writer.h"
#include "json.h"

#include <algorithm>
#include <cstring>
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

Status Trace::open(const std::string &path, TraceWriting how, bool record, const std::vector<TraceWireTopic> &wires,
		   int64_t realtime_origin_ns)
{
	// Written by the coordinator, between its requests: uncompressed, as
	// compressing cost a 1 kHz run 15 to 25 % more wall time; a thread of
	// its own compresses off the coordinator's core (docs/PERFORMANCE.md).
	writer_.emplace(McapWriterOptions{ .compression = how.by_caller ? McapCompression::none : McapCompression::zstd,
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
	if (auto s = open_wires(wires, realtime_origin_ns); !s)
		return s;
	buf_.resize(4096);
	set_joint_names(std::move(joint_names_));
	open_ = true;
	by_caller_ = how.by_caller;
	if (!by_caller_)
		thread_ = std::thread([this, avoid = how.avoid_cpu] { writer_loop(avoid); });
	return Ok{};
}

Status Trace::close()
{
	if (!open_)
		return Ok{};
	if (by_caller_) {
		while (pump()) {
		}
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

// What the thread is woken for: this much staged (some 100 cycles of a
// 1 kHz run); else it looks every 20 ms.
constexpr size_t kStagedEnough = 64 * 1024;
// By the caller: what a pump() writes at most (some 3 cycles of a 1 kHz
// run: a few microseconds), and past how much waiting the caller writes as
// it stages (a run that never leaves it idle, a world stepped back to back,
// keeps the trace's memory bounded all the same).
constexpr size_t kPumpBytes = 2048;
constexpr size_t kMostStaged = 1 << 20;

constexpr size_t kStagedHead = 2 + 8 + 4;

void Trace::put(uint16_t channel, int64_t v, size_t size)
{
	const uint64_t t = v < 0 ? 0 : (uint64_t)v;
	char head[kStagedHead];
	const uint32_t n = (uint32_t)size;
	std::memcpy(head, &channel, 2);
	std::memcpy(head + 2, &t, 8);
	std::memcpy(head + 10, &n, 4);
	if (by_caller_) {
		staged_.insert(staged_.end(), head, head + sizeof head);
		staged_.insert(staged_.end(), buf_.data(), buf_.data() + size);
		if (staged_.size() - staged_at_ > kMostStaged)
			pump();
		return;
	}
	bool enough;
	{
		std::lock_guard<std::mutex> lk(mu_);
		staged_.insert(staged_.end(), head, head + sizeof head);
		staged_.insert(staged_.end(), buf_.data(), buf_.data() + size);
		enough = staged_.size() >= kStagedEnough;
	}
	if (enough)
		cv_.notify_one();
}

bool Trace::pump()
{
	if (staged_at_ == staged_.size())
		return false;
	const size_t until = staged_at_ + kPumpBytes;
	while (staged_at_ < staged_.size() && staged_at_ < until)
		write_staged(staged_, &staged_at_);
	if (staged_at_ == staged_.size()) {
		staged_.clear(); // (its room kept)
		staged_at_ = 0;
	}
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
	std::vector<char> batch;
	for (;;) {
		{
			std::unique_lock<std::mutex> lk(mu_);
			// Written at least every 20 ms, so a killed run loses little.
			cv_.wait_for(lk, std::chrono::milliseconds(20),
				     [this] { return stop_ || staged_.size() >= kStagedEnough; });
			batch.swap(staged_);
			if (stop_ && batch.empty())
				return;
		}
		for (size_t at = 0; at < batch.size();)
			write_staged(batch, &at);
		batch.clear();
	}
}

void Trace::write_staged(const std::vector<char> &staged, size_t *at)
{
	uint16_t channel;
	uint64_t t;
	uint32_t n;
	std::memcpy(&channel, &staged[*at], 2);
	std::memcpy(&t, &staged[*at + 2], 8);
	std::memcpy(&n, &staged[*at + 10], 4);
	const char *data = &staged[*at + kStagedHead];
	*at += kStagedHead + n;
	if (!status_)
		return; // (after the first error, nothing more)
	if (auto s = writer_->write(channel, t, t, data, n); !s)
		status_ = s;
}

Status Trace::open_wires(const std::vector<TraceWireTopic> &wires, int64_t realtime_origin_ns)
{
	wires_.clear();
	uint16_t schemas[3] = {};
	for (const TraceWireTopic &wire : wires) {
		const WireSchema w = wire_schema(wire.kind);
		uint16_t &schema = schemas[int(wire.kind)];
		if (!schema) {
			auto id = writer_->add_schema(w.name, "ros2msg", w.definition);
			if (!id)
				return id.error();
			schema = *id;
		}
		// Its kind and name for readers (the candump export), and what a
		// receiving socket's CLOCK_REALTIME stamps add to virtual times.
		McapWriter::Metadata meta = { { "wire", w.kind },
					      { "name", wire.name },
					      { "realtime_origin_ns", std::to_string(realtime_origin_ns) } };
		auto channel = writer_->add_channel("/tcs/wire/" + wire.name, "cdr", schema, meta);
		if (!channel)
			return channel.error();
		wires_.push_back(*channel);
	}
	return Ok{};
}

void Trace::controller(int controller, const std::string &name, int pid, double cpu_scale, int mode,
			int64_t step_ns)
{
	JsonValue msg;
	msg.type = JsonValue::Type::Object;
	auto add = [&msg](const char *key, JsonValue x) { msg.object.emplace_back(key, std::move(x)); };
	add("controller", json_integer(controller));
	add("name", json_string(name));
	add("pid", json_integer(pid));
	add("cpu_scale", json_number(cpu_scale));
	add("mode", json_string(mode == 1 ? "lockstep" : "cpu"));
	add("step_ns", json_integer(step_ns));
	std::string text;
	json_append(text, msg);
	if (buf_.size() < text.size())
		buf_.resize(text.size());
	std::memcpy(buf_.data(), text.data(), text.size());
	put(controller_, 0, text.size());
}

void Trace::slice(int controller, const Slice &s)
{
	CdrWriter w(buf_);
	w.put<int32_t>(controller);
	// Nine int64s in a row: stored at once.
	const int64_t f[] = { s.v_start, s.v_end, s.charged_ns, s.cpu_ns, s.wall_start, s.wall_end, s.budget_ns,
			      s.overshoot_ns, s.sim_ns };
	std::memcpy(w.place(sizeof f, 8), f, sizeof f);
	w.put_string(s.why);
	put(slice_, s.v_start, w.size());
}

void Trace::wait(int controller, const char *kind, int64_t v_request, int64_t deadline, int64_t v_end, bool absolute)
{
	CdrWriter w(buf_);
	w.put<int32_t>(controller);
	w.put_string(kind);
	const int64_t f[] = { v_request, deadline == INT64_MAX ? -1 : deadline, v_end };
	std::memcpy(w.place(sizeof f, 8), f, sizeof f);
	w.put_bool(absolute);
	put(wait_, v_request, w.size());
}

void Trace::command(int controller, std::string_view path, int64_t v, std::span<const double> values, bool malformed)
{
	CdrWriter w(buf_);
	w.put<int32_t>(controller);
	w.put_string(path);
	w.put<int64_t>(v);
	w.put_count(values.size());
	w.put_array(values.data(), values.size());
	w.put_bool(malformed);
	put(device_, v, w.size());
}

void Trace::set_joint_names(std::vector<std::string> names)
{
	joint_names_ = std::move(names);
	// Encoded where a step's names go, right after its three times (8-byte
	// aligned there as at the header's end), then kept without the header.
	std::string block;
	CdrWriter w(block);
	w.put_count(joint_names_.size());
	for (const std::string &name : joint_names_)
		w.put_string(name);
	step_names_.assign(w.view().substr(4));
}

void Trace::step(int64_t v, int64_t wall_ns, int64_t wall_cost_ns, std::span<const double> joint_values)
{
	const size_t n = std::min(joint_values.size(), joint_names_.size());
	CdrWriter w(buf_);
	const int64_t f[] = { v, wall_ns, wall_cost_ns };
	std::memcpy(w.place(sizeof f, 8), f, sizeof f);
	if (n == joint_names_.size()) {
		w.put_bytes(step_names_.data(), step_names_.size());
	} else {
		w.put_count(n);
		for (size_t i = 0; i < n; i++)
			w.put_string(joint_names_[i]);
	}
	w.put_count(n);
	w.put_array(joint_values.data(), n);
	put(step_, v, w.size());
	CdrWriter clock(buf_);
	clock.put<int32_t>((int32_t)(v / 1000000000));
	clock.put<uint32_t>((uint32_t)(v % 1000000000));
	put(clock_, v, clock.size());
}

void Trace::record_run(const std::string &json)
{
	if (buf_.size() < json.size())
		buf_.resize(json.size());
	std::memcpy(buf_.data(), json.data(), json.size());
	put(record_run_, 0, json.size());
}

void Trace::journal(int controller, std::span<const tcs_journal_entry> entries)
{
	if (entries.empty())
		return;
	CdrWriter w(buf_);
	w.put<int32_t>(controller);
	w.put_count(entries.size());
	// Each entry 24 bytes, 8-aligned, its fields in its own order:
	// kind (u16), type (u16), thread (u32), value (i64), arg (i64).
	char *out = w.place(entries.size() * 24, 8);
	int64_t at = 0;
	for (const tcs_journal_entry &j : entries) {
		std::memcpy(out, &j.kind, 2);
		std::memcpy(out + 2, &j.type, 2);
		std::memcpy(out + 4, &j.thread, 4);
		std::memcpy(out + 8, &j.value, 8);
		std::memcpy(out + 16, &j.arg, 8);
		out += 24;
		if (j.kind == TCS_J_CLOCK || j.kind == TCS_J_CHARGE || j.kind == TCS_J_READ)
			at = j.value;
	}
	put(journal_, at, w.size()); // (logged at its last virtual time)
}

void Trace::can_frame(size_t wire, const TraceCanFrame &f)
{
	if (wire < wires_.size())
		put(wires_[wire], f.v_end, encode_can_frame(buf_, f));
}

void Trace::serial_bytes(size_t wire, const TraceSerialBytes &b)
{
	if (wire < wires_.size())
		put(wires_[wire], b.v_end, encode_serial_bytes(buf_, b));
}

void Trace::i2c_transfer(size_t wire, const TraceI2cTransfer &x)
{
	if (wire < wires_.size())
		put(wires_[wire], x.v_end, encode_i2c_transfer(buf_, x));
}

} // namespace tcs
