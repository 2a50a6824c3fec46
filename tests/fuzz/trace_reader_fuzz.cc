// The fuzz target for the trace reader: an input is read as an MCAP file,
// every message's data parsed as JSON; an input that is not MCAP at all is
// parsed as one JSON text, so that JSON seeds fuzz the parser directly.
// Built with libFuzzer (clang) or with standalone_driver.cc (its seeds are
// in trace_reader_seeds.cc); either way a crash, a sanitizer report or a
// broken promise of the API aborts.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "fuzz_target.h"
#include "json.h"
#include "mcap_reader.h"

namespace {

// The reader is linear in its input, but a zstd chunk may hold 32768 times
// its size: a bound on messages keeps one input's work small.
constexpr size_t kMaxMessages = 20000;

using tcs_fuzz::check;

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
	}
	return 0;
}
