// export_trace: CSV and JSON straight from the MCAP messages (so they work
// on any topic), Chrome Trace Events from the typed records.
#include "trace_export.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <map>
#include <vector>

#include "json.h"
#include "message_decode.h"
#include "trace_candump.h"
#include "trace_data.h"

namespace tcs {

namespace {

// Every message of the file (of topic, if not empty), to f.
Status each_message(const std::string &path, const std::string &topic,
		    const std::function<Status(const McapMessage &)> &f)
{
	return for_each_message(path, [&](const McapMessage &m) {
		return topic.empty() || m.channel->topic == topic ? f(m) : Status(Ok{});
	});
}

Result<JsonValue> decode_message(MessageDecoder &decoder, const std::string &path, const McapMessage &m)
{
	auto v = decoder.decode(m);
	if (!v)
		return Error{ path + ": " + m.channel->topic + " message " + std::to_string(m.sequence) + ": " +
			      v.error().message };
	return v;
}

// X_names and X_values, arrays of a name for each value (a step's joint
// states): the values, by name, or null.
const JsonValue *named_values(const JsonValue &object, const std::string &key)
{
	if (key.size() <= 6 || key.compare(key.size() - 6, 6, "_names") != 0)
		return nullptr;
	const JsonValue *names = object.get(key);
	const JsonValue *values = object.get(key.substr(0, key.size() - 6) + "_values");
	if (!values || names->type != JsonValue::Type::Array || values->type != JsonValue::Type::Array ||
	    names->array.size() != values->array.size())
		return nullptr;
	for (const JsonValue &n : names->array)
		if (n.type != JsonValue::Type::String)
			return nullptr;
	return values;
}

// Flattens a JSON value into (column, text) pairs: objects by "a.b",
// arrays by "a[0]", and X_names with X_values by "X.name" (a column per
// joint, as a JSON trace's "joints" object gave).
void flatten(const std::string &prefix, const JsonValue &v, std::vector<std::pair<std::string, std::string>> &out)
{
	char buf[64];
	switch (v.type) {
	case JsonValue::Type::Object: {
		std::vector<std::string> paired;
		for (const auto &[k, x] : v.object) {
			if (std::find(paired.begin(), paired.end(), k) != paired.end())
				continue;
			const std::string key = prefix.empty() ? k : prefix + "." + k;
			if (const JsonValue *values = named_values(v, k)) {
				const std::string stem = key.substr(0, key.size() - 6) + ".";
				for (size_t i = 0; i < values->array.size(); i++)
					flatten(stem + x.array[i].string, values->array[i], out);
				paired.push_back(k.substr(0, k.size() - 6) + "_values");
				continue;
			}
			flatten(key, x, out);
		}
		return;
	}
	case JsonValue::Type::Array:
		for (size_t i = 0; i < v.array.size(); i++)
			flatten(prefix + "[" + std::to_string(i) + "]", v.array[i], out);
		return;
	case JsonValue::Type::Null:
		out.emplace_back(prefix, "");
		return;
	case JsonValue::Type::Bool:
		out.emplace_back(prefix, v.boolean ? "true" : "false");
		return;
	case JsonValue::Type::Number:
		if (v.is_integer)
			snprintf(buf, sizeof buf, "%" PRId64, v.integer);
		else
			snprintf(buf, sizeof buf, "%.17g", v.number);
		out.emplace_back(prefix, buf);
		return;
	case JsonValue::Type::String:
		out.emplace_back(prefix, v.string);
		return;
	}
}

void csv_cell(std::string &line, const std::string &text)
{
	if (text.find_first_of(",\"\r\n") == std::string::npos) {
		line += text;
		return;
	}
	line += '"';
	for (char c : text) {
		if (c == '"')
			line += '"';
		line += c;
	}
	line += '"';
}

Status export_csv(const std::string &path, const std::string &topic, FILE *out)
{
	// Two passes: the columns are every field any message has, in the
	// order they first appear.
	std::vector<std::string> columns;
	std::map<std::string, size_t> index;
	uint64_t rows = 0;
	std::vector<std::pair<std::string, std::string>> cells;
	MessageDecoder decoder;
	auto s = each_message(path, topic, [&](const McapMessage &m) -> Status {
		auto v = decode_message(decoder, path, m);
		if (!v)
			return v.error();
		cells.clear();
		flatten("", *v, cells);
		for (const auto &[k, text] : cells)
			if (index.emplace(k, columns.size()).second)
				columns.push_back(k);
		rows++;
		return Ok{};
	});
	if (!s)
		return s;
	if (!rows)
		return Error{ path + ": no messages on topic " + topic };
	std::string line = "log_time_ns";
	for (const auto &c : columns) {
		line += ',';
		csv_cell(line, c);
	}
	line += '\n';
	fputs(line.c_str(), out);
	std::vector<std::string> row(columns.size());
	return each_message(path, topic, [&](const McapMessage &m) -> Status {
		auto v = decode_message(decoder, path, m);
		if (!v)
			return v.error();
		cells.clear();
		flatten("", *v, cells);
		for (auto &r : row)
			r.clear();
		for (auto &[k, text] : cells)
			row[index.at(k)] = std::move(text);
		line = std::to_string(m.log_time);
		for (const auto &r : row) {
			line += ',';
			csv_cell(line, r);
		}
		line += '\n';
		fputs(line.c_str(), out);
		return Ok{};
	});
}

Status export_json(const std::string &path, const std::string &topic, FILE *out)
{
	std::string head = "{\"path\":";
	json_append_string(head, path);
	head += ",\"messages\":[";
	fputs(head.c_str(), out);
	bool first = true;
	std::string line;
	MessageDecoder decoder;
	auto s = each_message(path, topic, [&](const McapMessage &m) -> Status {
		// Decoded to check it; JSON then written as it was.
		auto v = decode_message(decoder, path, m);
		if (!v)
			return v.error();
		line = first ? "\n" : ",\n";
		first = false;
		line += "{\"topic\":";
		json_append_string(line, m.channel->topic);
		line += ",\"log_time_ns\":" + std::to_string(m.log_time) + ",\"sequence\":" + std::to_string(m.sequence) +
			",\"data\":";
		if (m.channel->message_encoding == "json")
			line.append(m.data.data(), m.data.size());
		else
			json_append(line, *v);
		line += '}';
		fputs(line.c_str(), out);
		return Ok{};
	});
	fputs("\n]}\n", out);
	return s;
}

// Trace Event timestamps are microseconds; keep the nanoseconds.
std::string us(int64_t ns)
{
	char buf[40];
	snprintf(buf, sizeof buf, "%" PRId64 ".%03d", ns / 1000, (int)(ns % 1000));
	return buf;
}

Status export_chrome(const std::string &path, FILE *out)
{
	auto loaded = load_trace(path);
	if (!loaded)
		return loaded.error();
	const TraceData &t = *loaded;
	std::string o = "{\"displayTimeUnit\":\"ns\",\"otherData\":{\"trace\":";
	json_append_string(o, path);
	o += ",\"time\":\"virtual\"},\"traceEvents\":[\n";
	o += "{\"name\":\"process_name\",\"ph\":\"M\",\"pid\":1,\"args\":{\"name\":\"tcs (virtual time)\"}},\n";
	o += "{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":1,\"tid\":0,\"args\":{\"name\":\"simulation\"}}";
	for (const auto &c : t.controllers) {
		o += ",\n{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":1,\"tid\":" + std::to_string(c.id) +
		     ",\"args\":{\"name\":";
		json_append_string(o, "controller " + std::to_string(c.id) + ": " + c.name);
		o += "}}";
	}
	auto flush = [&] {
		fputs(o.c_str(), out);
		o.clear();
	};
	static const char *ends[] = { "blocked", "preempted", "exited", "ended" };
	for (const auto &s : t.slices) {
		o += ",\n{\"name\":\"running\",\"cat\":\"slice\",\"ph\":\"X\",\"pid\":1,\"tid\":" +
		     std::to_string(s.controller) + ",\"ts\":" + us(s.v_start) + ",\"dur\":" + us(s.v_end - s.v_start) +
		     ",\"args\":{\"end\":\"" + ends[(int)s.end] + "\",\"charged_ns\":" + std::to_string(s.charged) +
		     ",\"wall_start_ns\":" + std::to_string(s.wall_start) + ",\"wall_end_ns\":" +
		     std::to_string(s.wall_end) + "}}";
		if (o.size() > 1 << 16)
			flush();
	}
	for (const auto &w : t.waits) {
		o += ",\n{\"name\":";
		json_append_string(o, w.kind);
		o += ",\"cat\":\"wait\",\"ph\":\"X\",\"pid\":1,\"tid\":" + std::to_string(w.controller) +
		     ",\"ts\":" + us(w.v_request) + ",\"dur\":" + us(w.v_end - w.v_request) + ",\"args\":{\"deadline_ns\":" +
		     std::to_string(w.deadline) + ",\"absolute\":" + (w.absolute ? "true" : "false") + "}}";
		if (w.missed())
			o += ",\n{\"name\":\"deadline miss\",\"cat\":\"wait\",\"ph\":\"i\",\"s\":\"t\",\"pid\":1,\"tid\":" +
			     std::to_string(w.controller) + ",\"ts\":" + us(w.v_request) + ",\"args\":{\"late_ns\":" +
			     std::to_string(w.v_request - w.deadline) + "}}";
		if (o.size() > 1 << 16)
			flush();
	}
	for (const auto &c : t.commands) {
		o += ",\n{\"name\":\"command\",\"cat\":\"device\",\"ph\":\"i\",\"s\":\"t\",\"pid\":1,\"tid\":" +
		     std::to_string(c.controller) + ",\"ts\":" + us(c.v) + ",\"args\":{\"path\":";
		json_append_string(o, c.path);
		o += ",\"values\":[";
		for (size_t i = 0; i < c.values.size(); i++) {
			char buf[40];
			snprintf(buf, sizeof buf, std::isfinite(c.values[i]) ? "%.17g" : "null", c.values[i]);
			o += (i ? "," : "") + std::string(buf);
		}
		o += std::string("],\"malformed\":") + (c.malformed ? "true" : "false") + "}}";
		if (o.size() > 1 << 16)
			flush();
	}
	int64_t step = t.controllers.empty() ? 0 : t.controllers.front().step_ns;
	for (const auto &s : t.steps) {
		o += ",\n{\"name\":\"step\",\"cat\":\"simulation\",\"ph\":\"X\",\"pid\":1,\"tid\":0,\"ts\":" +
		     us(s.v - step) + ",\"dur\":" + us(step) + ",\"args\":{\"wall_cost_ns\":" + std::to_string(s.wall_cost) +
		     "}}";
		// Joint states as counter tracks.
		for (size_t i = 0; i < s.joints.size(); i++) {
			if (!std::isfinite(s.joints[i]))
				continue;
			char buf[40];
			snprintf(buf, sizeof buf, "%.17g", s.joints[i]);
			o += ",\n{\"name\":";
			json_append_string(o, t.joint_names[i]);
			o += ",\"cat\":\"simulation\",\"ph\":\"C\",\"pid\":1,\"ts\":" + us(s.v) + ",\"args\":{\"value\":" +
			     buf + "}}";
		}
		if (o.size() > 1 << 16)
			flush();
	}
	o += "\n]}\n";
	flush();
	return Ok{};
}

} // namespace

Status export_trace(const std::string &path, ExportFormat format, const std::string &topic, FILE *out)
{
	switch (format) {
	case ExportFormat::Csv:
		return export_csv(path, topic, out);
	case ExportFormat::Json:
		return export_json(path, topic, out);
	case ExportFormat::Chrome:
		return export_chrome(path, out);
	case ExportFormat::Candump:
		return export_candump(path, topic, out);
	}
	return Error{ "unknown format" };
}

} // namespace tcs
