// The fuzz target for the trace reader: an input is read as an MCAP file,
// every message decoded by its channel's encoding (JSON parsed, CDR by its
// ros2msg schema) and, JSON or not, parsed as JSON, and every top-level record decoded
// as its kind (what a streaming read skips too); an input that is not MCAP
// at all is parsed as one JSON text, so that JSON seeds fuzz the parser
// directly. Built with libFuzzer (clang) or with standalone_driver.cc;
// either way a crash, a sanitizer report or a broken promise of the API
// aborts. Its seeds are a trace and a record written by tcs::Trace (CDR
// and JSON topics), traces written by McapWriter (zstd, uncompressed,
// with CRCs zeroed, unchunked, cut in half) and JSON texts; its mutation
// makes an MCAP record's length, or a chunk's sizes, lie: what the reader
// trusts least.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_target.h"
#include "json.h"
#include "message_decode.h"
#include "mcap_format.h"
#include "mcap_reader.h"
#include "mcap_records.h"
#include "mcap_writer.h"
#include "trace.h"

namespace {

// The reader is linear in its input, but a zstd chunk may hold 32768 times
// its size: a bound on messages keeps one input's work small.
constexpr size_t kMaxMessages = 20000;

using tcs_fuzz::check;
using tcs_fuzz::get_le;
using tcs_fuzz::put_le;

// Every string the parser returns is text json_append_string writes so
// that it parses back unchanged.
void check_strings(const tcs::JsonValue &v)
{
	auto round_trip = [](const std::string &s) {
		std::string literal;
		tcs::json_append_string(literal, s);
		auto back = tcs::json_parse(literal);
		check(back.ok() && back->type == tcs::JsonValue::Type::String && back->string == s);
	};
	switch (v.type) {
	case tcs::JsonValue::Type::String:
		round_trip(v.string);
		break;
	case tcs::JsonValue::Type::Array:
		for (const tcs::JsonValue &x : v.array)
			check_strings(x);
		break;
	case tcs::JsonValue::Type::Object:
		for (const auto &[key, x] : v.object) {
			round_trip(key);
			check_strings(x);
		}
		break;
	default:
		break;
	}
}

void parse_json(std::string_view text)
{
	auto v = tcs::json_parse(text);
	if (!v.ok()) {
		check(v.error().message.rfind("at byte ", 0) == 0);
		return;
	}
	check_strings(*v);
}

// A message as its channel's encoding says: decoded, it writes as JSON that
// parses; refused, one line says why.
void decode_message(tcs::MessageDecoder &decoder, const tcs::McapMessage &m)
{
	auto v = decoder.decode(m);
	if (!v.ok()) {
		check(!v.error().message.empty() && v.error().message.find('\n') == std::string::npos);
		return;
	}
	std::string text;
	tcs::json_append(text, *v);
	check(tcs::json_parse(text).ok());
}

// Every top-level record through the decoder of its kind: what it accepts
// lies within the record, and what it read is no more than the record.
void decode_records(std::string_view f)
{
	tcs::McapRecord r;
	size_t n = 0;
	for (uint64_t pos = sizeof tcs::kMcapMagic; n < kMaxMessages && tcs::mcap_record_at(f, pos, &r);
	     pos += tcs::kMcapRecordHead + r.body.size(), n++) {
		check(r.offset == pos && r.body.data() == f.data() + pos + tcs::kMcapRecordHead);
		auto inside = [&](std::string_view v) {
			check(v.empty() || (v.data() >= r.body.data() && v.data() + v.size() <= r.body.data() + r.body.size()));
		};
		size_t known = SIZE_MAX;
		std::string what = "not decoded";
		switch (r.op) {
		case tcs::mcap_header: {
			tcs::McapHeader h;
			if ((what = tcs::mcap_decode_header(r.body, &h, &known)).empty())
				inside(h.profile), inside(h.library);
			break;
		}
		case tcs::mcap_chunk: {
			tcs::McapChunk c;
			if ((what = tcs::mcap_decode_chunk(r.body, &c, &known)).empty())
				inside(c.compression), inside(c.records);
			break;
		}
		case tcs::mcap_message_index: {
			tcs::McapMessageIndex mi;
			if ((what = tcs::mcap_decode_message_index(r.body, &mi, &known)).empty())
				check(mi.records.size() * 16 <= r.body.size());
			break;
		}
		case tcs::mcap_chunk_index: {
			tcs::McapChunkIndex ci;
			if ((what = tcs::mcap_decode_chunk_index(r.body, &ci, &known)).empty())
				inside(ci.compression), check(ci.message_index_offsets.size() * 10 <= r.body.size());
			break;
		}
		case tcs::mcap_statistics: {
			tcs::McapStatistics s;
			if ((what = tcs::mcap_decode_statistics(r.body, &s, &known)).empty())
				check(s.channel_message_counts.size() * 10 <= r.body.size());
			break;
		}
		case tcs::mcap_summary_offset: {
			tcs::McapSummaryOffset so;
			what = tcs::mcap_decode_summary_offset(r.body, &so, &known);
			break;
		}
		case tcs::mcap_footer: {
			tcs::McapFooter ft;
			what = tcs::mcap_decode_footer(r.body, &ft, &known);
			break;
		}
		case tcs::mcap_data_end: {
			uint32_t crc;
			what = tcs::mcap_decode_data_end(r.body, &crc, &known);
			break;
		}
		default:
			break;
		}
		// Accepted: read no more than the record; refused: one line, saying what.
		if (what.empty())
			check(known <= r.body.size());
		else
			check(what.find('\n') == std::string::npos);
	}
}

// The offsets of the complete top-level records of an MCAP file.
std::vector<size_t> records(const std::string &f)
{
	std::vector<size_t> out;
	for (size_t pos = 8; pos < f.size() && f.size() - pos >= 9;) {
		uint64_t len = get_le(f, pos + 1);
		if (len > f.size() - pos - 9)
			break;
		out.push_back(pos);
		pos += 9 + size_t(len);
	}
	return out;
}

// A trace as tcs writes them, in memory.
std::string written_trace(tcs::McapCompression compression, int messages)
{
	return tcs_fuzz::written_file([&](const std::string &path) {
		tcs::McapWriter w(tcs::McapWriterOptions{ .chunk_size = 300, .compression = compression });
		if (!w.open(path, "x-tcs", "fuzz").ok())
			return;
		auto schema = w.add_schema("tcs.Slice", R"({"type":"object"})");
		auto a = w.add_channel("/tcs/slices", schema.ok() ? *schema : 0, { { "controller", "pd" } });
		auto b = w.add_channel("/clock", 0);
		for (int i = 0; i < messages && a.ok() && b.ok(); i++) {
			std::string json = i % 3 ? "{\"t_ns\":" + std::to_string(1000 * i) + "}"
						 : "{\"name\":\"c\\u00e9\\ud83d\\ude00\\n\",\"v\":[1,-2.5e-3,9007199254740993,true,"
						   "null,{\"x\":[]}],\"i\":" +
							   std::to_string(i) + "}";
			(void)w.write(i % 3 ? *b : *a, uint64_t(i), uint64_t(i), json);
		}
		(void)w.close();
	});
}

// A trace (or a record) as tcs::Trace writes a run's: its CDR and JSON
// topics, small chunks.
std::string tcs_trace(bool record)
{
	return tcs_fuzz::written_file([&](const std::string &path) {
		tcs::Trace t;
		const std::vector<tcs::TraceWireTopic> wires = { { tcs::TraceWireKind::can, "can0" },
								 { tcs::TraceWireKind::serial, "dev/ttyUSB0" },
								 { tcs::TraceWireKind::i2c, "dev/i2c-1" } };
		if (!t.open(path, tcs::TraceWriting{ .by_caller = true }, record, wires, 1700000000000000000).ok())
			return;
		static const std::string name = "pd \"ctl\"", torque = "/dev/tcs/p/torque";
		t.controller(1, name, 42, 1.5, 0, 1000000);
		t.set_joint_names({ "p.hinge.position", "p.hinge.velocity" });
		for (int i = 0; i < 3; i++) {
			int64_t v = 1000000LL * i;
			t.slice(1, { v, v + 900, 900, 1000, v / 40, v / 40 + 1000, i == 1 ? 5000 : -1, i == 1 ? 7 : 0, v, "blocked" });
			t.wait(1, "nanosleep", v + 900, v + 1000000, v + 1000050, i % 2);
			t.command(1, torque, v + 800, std::vector<double>{ 0.5 * i, -1e300 }, i == 2);
			t.step(v + 1000000, v / 40, 7000, std::vector<double>{ 3.1 - 0.01 * i, 0.2 });
		}
		static const uint8_t bytes[] = { 0xff, 0xff, 0xfd, 0x00, 0x01, 0x03, 0x00, 0x01, 0x19, 0x4e };
		t.can_frame(0, { 10, 91, 0x123, false, 0, std::span(bytes, 4), "cansend", "" });
		t.can_frame(0, { 91, 160, 0x80000042 | 0x40000000, false, 0, std::span(bytes, 3), "motor 1", "a remote frame" });
		t.can_frame(0, { 160, 200, 0x7ff, true, 1, std::span(bytes, 10), name, "" });
		t.serial_bytes(1, { 0, 1736, bytes, name, "" });
		t.serial_bytes(1, { 1736, 1736, {}, "servos", "its CRC does not match" });
		const tcs::TraceI2cMessage msgs[] = { { 0x68, 0, std::span(bytes, 1) }, { 0x68, 1, std::span(bytes + 1, 6) } };
		t.i2c_transfer(2, { 0, 97500, 0, msgs, name, "" });
		t.i2c_transfer(2, { 97500, 125000, -6, std::span(msgs, 1), name, "no chip at 0x68" });
		t.journal(1, std::vector<tcs_journal_entry>{ { 100, 0, 1, 0, 0 }, { 900, 0, 4, 7, 0 }, { 1000900, 12, 5, 3, 0 } });
		(void)t.close();
	});
}

// The same trace with its chunks' CRCs zeroed ("not computed"), so that
// mutations of their records reach the record and JSON parsers; and with
// the records taken out of their chunks, as messages outside any chunk.
std::string without_crcs(std::string f)
{
	for (size_t at : records(f))
		if (f[at] == 0x06 && f.size() - at >= 9 + 28)
			put_le(f, at + 9 + 24, 0, 4);
	return f;
}

std::string unchunked(const std::string &f)
{
	std::string out = f.substr(0, 8);
	for (size_t at : records(f)) {
		const size_t len = size_t(get_le(f, at + 1));
		if (f[at] == 0x07) // Message Index: points into chunks no more
			continue;
		const size_t records_len_at = at + 9 + 28 + 4; // past an empty compression string
		if (f[at] == 0x06 && len >= 28 + 4 + 8 && get_le(f, at + 9 + 28, 4) == 0) // uncompressed
			out += f.substr(records_len_at + 8, size_t(get_le(f, records_len_at)));
		else
			out += f.substr(at, 9 + len);
	}
	return out + f.substr(f.size() - 8);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const std::string_view input(reinterpret_cast<const char *>(data), size);
	tcs::McapReader reader;
	tcs::Status opened = reader.open_bytes("fuzz", std::string(input));
	if (!opened.ok()) {
		const std::string &e = opened.error().message;
		check(e == "fuzz: not an MCAP file" || e.rfind("fuzz: at byte ", 0) == 0);
		if (e == "fuzz: not an MCAP file")
			parse_json(input);
		return 0;
	}
	decode_records(input);
	tcs::MessageDecoder decoder;
	for (size_t n = 0; n < kMaxMessages; n++) {
		tcs::McapMessage m;
		auto more = reader.next(&m);
		if (!more.ok()) {
			check(more.error().message.rfind("fuzz: at byte ", 0) == 0);
			break;
		}
		if (!*more) {
			check(reader.bytes_unread() <= size);
			check(reader.truncated() || reader.bytes_unread() == 0);
			break;
		}
		check(m.channel && m.channel == &reader.channels().at(m.channel->id));
		check(m.channel->schema_id == 0 ? !m.schema : m.schema == &reader.schemas().at(m.channel->schema_id));
		parse_json(m.data);
		decode_message(decoder, m);
	}
	return 0;
}

const char *tcs_fuzz_name()
{
	return "trace_reader_fuzz";
}

std::vector<std::string> tcs_fuzz_seeds()
{
	std::string zstd = written_trace(tcs::McapCompression::zstd, 40);
	std::string none = written_trace(tcs::McapCompression::none, 40);
	return {
		tcs_trace(false),
		tcs_trace(true),
		without_crcs(tcs_trace(true)), // (its CDR reached by mutations)
		zstd,
		none,
		without_crcs(none),
		unchunked(none),
		zstd.substr(0, zstd.size() / 2),
		written_trace(tcs::McapCompression::zstd, 0),
		R"({"a":[1,2.5e10,-0,"x\"\\\/\b\f\n\r\t\u0041\ud83d\ude00"],"b":{"c":null,"d":true,"e":false}})",
		"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]",
		"-9223372036854775808 ",
		"\"\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80\"",
	};
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { "\x89MCAP0\r\n", "\\u", "\\ud800", "\\udc00", "1e400", "-0", "true", "null", "\"\":" };
}

// A record's length, or a chunk's sizes, made to lie.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	std::vector<size_t> recs = records(s);
	if (recs.empty())
		return false;
	size_t at = recs[rng.below(recs.size())];
	const size_t fields[] = { 1, 9 + 16, 9 + 24, 9 + 28, 9 + 32 }; // len, usize, crc, compression, records len
	const size_t field = s[at] == 0x06 ? fields[rng.below(5)] : 1;
	const int bytes = field == 9 + 24 || field == 9 + 28 ? 4 : 8;
	const uint64_t v = rng.below(2) ? tcs_fuzz::lying_value(rng, s.size())
					: get_le(s, at + field, bytes) + rng.below(17) - 8;
	put_le(s, at + field, v, bytes);
	return true;
}
