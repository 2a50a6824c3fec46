// The reader tests' shared checks and files (see mcap_read_checks.h).
#include "mcap_read_checks.h"

#include <csetjmp>
#include <cstdarg>
#include <cstddef>

extern "C" {
#include <cmocka.h>
}

#include "result_checks.h"

#include "mcap_reader.h"
#include "test_files.h"

namespace mcap_read_checks {

using tcs::McapMessage;
using tcs::McapReader;
using tcs::McapWriterOptions;

Outcome read_bytes(const std::string &name, std::string bytes)
{
	Outcome o;
	McapReader r;
	tcs::Status s = r.open_bytes(name, std::move(bytes));
	if (!s) {
		o.error = s.error().message;
		return o;
	}
	o.opened = true;
	for (;;) {
		McapMessage m;
		auto more = r.next(&m);
		if (!more) {
			o.error = more.error().message;
			// The error sticks.
			auto again = r.next(&m);
			assert_false(again.ok());
			assert_string_equal(again.error().message.c_str(), o.error.c_str());
			return o;
		}
		if (!*more)
			break;
		assert_non_null(m.channel);
		assert_true(m.channel->schema_id == 0 ? m.schema == nullptr : m.schema && m.schema->id == m.channel->schema_id);
		o.messages.push_back(Msg{ m.channel->id, m.channel->topic, m.schema ? m.schema->name : "", m.sequence,
					  m.log_time, m.publish_time, std::string(m.data) });
	}
	o.truncated = r.truncated();
	o.unread = r.bytes_unread();
	McapMessage m;
	auto after = r.next(&m); // the end stays the end
	assert_true(after.ok() && !*after);
	return o;
}

void expect_error(const Outcome &o, const std::string &part1, const std::string &part2)
{
	if (o.error.empty() || o.error.find(part1) == std::string::npos || o.error.find(part2) == std::string::npos) {
		print_error("got error '%s' after %zu messages; expected one naming '%s' and '%s'\n", o.error.c_str(),
			    o.messages.size(), part1.c_str(), part2.c_str());
		fail();
	}
}

void expect_complete(const Outcome &o, size_t messages)
{
	if (!o.error.empty() || o.truncated || o.messages.size() != messages) {
		print_error("error '%s', truncated %d, %zu messages; expected a complete file of %zu\n", o.error.c_str(),
			    o.truncated, o.messages.size(), messages);
		fail();
	}
}

const char kClockSchema[] = R"({"type":"object","properties":{"t_ns":{"type":"integer"}}})";
const char kSliceSchema[] = R"({"type":"object","properties":{"controller":{"type":"string"}}})";

void Sample::write(McapWriter &w, int count)
{
	uint16_t clock = MUST(w.add_schema("tcs.Clock", kClockSchema));
	uint16_t slice = MUST(w.add_schema("tcs.Slice", kSliceSchema));
	struct {
		uint16_t id;
		const char *topic, *schema;
		uint32_t seq;
	} ch[4] = {
		{ MUST(w.add_channel("/clock", clock)), "/clock", "tcs.Clock", 0 },
		{ MUST(w.add_channel("/tcs/slices/a", slice)), "/tcs/slices/a", "tcs.Slice", 0 },
		{ MUST(w.add_channel("/tcs/slices/b", slice, { { "controller", "b" } })), "/tcs/slices/b", "tcs.Slice", 0 },
		{ MUST(w.add_channel("/raw", 0)), "/raw", "", 0 },
	};
	for (int i = 0; i < count; i++) {
		auto &c = ch[(i * 7) % 11 % 4];
		uint64_t t = 1'000'000 + 997 * uint64_t(i);
		std::string json = "{\"t_ns\":" + std::to_string(t) + ",\"controller\":\"c" + std::to_string(i % 3) +
				   std::string(i % 17, 'x') + "\",\"big\":9007199254740993,\"f\":-1.5e-3}";
		uint32_t chunks = w.chunk_count();
		CHECK_OK(w.write(c.id, t, t + 3, json));
		expected.push_back(Msg{ c.id, c.topic, c.schema, c.seq++, t, t + 3, json });
		if (w.chunk_count() != chunks)
			messages_after_chunk.push_back(expected.size());
	}
}

std::string write_sample(const char *name, McapCompression compression, size_t chunk_size, int count, Sample &s)
{
	std::string path = test_files::test_path(name);
	McapWriter w(McapWriterOptions{ .chunk_size = chunk_size, .compression = compression });
	CHECK_OK(w.open(path, "x-tcs", "tcs test"));
	s.write(w, count);
	uint32_t chunks = w.chunk_count();
	CHECK_OK(w.close());
	if (w.chunk_count() != chunks)
		s.messages_after_chunk.push_back(s.expected.size());
	return path;
}

Layout layout(const std::string &f)
{
	Layout l;
	size_t pos = 8;
	while (f.size() - pos >= 9) {
		uint64_t len = 0;
		for (int i = 0; i < 8; i++)
			len |= uint64_t(uint8_t(f[pos + 1 + i])) << (8 * i);
		if (len > f.size() - pos - 9)
			break;
		uint8_t op = uint8_t(f[pos]);
		if (op == 0x06)
			l.chunk_starts.push_back(pos);
		pos += 9 + len;
		l.record_ends.push_back(pos);
		if (op == 0x06)
			l.chunk_ends.push_back(pos);
		if (op == 0x02)
			break;
	}
	return l;
}

} // namespace mcap_read_checks
