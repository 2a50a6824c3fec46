// ros2msg: definitions parsed line by line into types, then CDR decoded
// field by field with every length checked against the bytes left.
#include "ros2msg.h"

#include "mcap_records.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <type_traits>

namespace tcs {

namespace {

constexpr size_t kMostDepth = 32;        // nested types within types
constexpr uint32_t kMostFixed = 1 << 20; // elements of a fixed-size array

std::string_view trim(std::string_view s)
{
	while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
		s.remove_prefix(1);
	while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
		s.remove_suffix(1);
	return s;
}

// "pkg/msg/Name" and "pkg/Name" are one type.
std::string normal_name(std::string_view name)
{
	std::string s(name);
	if (size_t at = s.find("/msg/"); at != std::string::npos)
		s.erase(at, 4);
	return s;
}

bool primitive(std::string_view t, Ros2Field::Kind *kind)
{
	using K = Ros2Field::Kind;
	static const struct {
		const char *name;
		K kind;
	} kinds[] = { { "bool", K::Bool },       { "byte", K::Uint8 },     { "char", K::Uint8 },     { "int8", K::Int8 },
		      { "uint8", K::Uint8 },     { "int16", K::Int16 },    { "uint16", K::Uint16 },  { "int32", K::Int32 },
		      { "uint32", K::Uint32 },   { "int64", K::Int64 },    { "uint64", K::Uint64 },  { "float32", K::Float32 },
		      { "float64", K::Float64 }, { "string", K::String } };
	if (t.rfind("string<=", 0) == 0)
		t = "string";
	for (const auto &k : kinds)
		if (t == k.name) {
			*kind = k.kind;
			return true;
		}
	return false;
}

bool is_separator(std::string_view line)
{
	return line.size() >= 3 && line.find_first_not_of('=') == std::string_view::npos;
}

struct Pending {
	size_t type, field;
	std::string name; // the nested type as written
	int line;
};

} // namespace

Result<Ros2Msg> ros2msg_parse(std::string_view name, std::string_view text)
{
	Ros2Msg msg;
	msg.types.push_back(Ros2Type{ normal_name(name), {} });
	std::vector<Pending> pending;
	bool want_msg_line = false;
	int line_no = 0;
	auto fail = [&](const std::string &what) -> Error { return Error{ "line " + std::to_string(line_no) + ": " + what }; };
	while (!text.empty()) {
		size_t nl = text.find('\n');
		std::string_view line = text.substr(0, nl);
		text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
		line_no++;
		line = trim(line);
		if (is_separator(line)) {
			want_msg_line = true;
			continue;
		}
		if (size_t hash = line.find('#'); hash != std::string_view::npos)
			line = trim(line.substr(0, hash));
		if (line.empty())
			continue;
		if (want_msg_line) {
			if (line.rfind("MSG:", 0) != 0)
				return fail("a section that does not start with 'MSG: type'");
			msg.types.push_back(Ros2Type{ normal_name(trim(line.substr(4))), {} });
			want_msg_line = false;
			continue;
		}
		size_t sp = line.find_first_of(" \t");
		if (sp == std::string_view::npos)
			return fail("a field without a name: '" + printable(line) + "'");
		std::string_view type = line.substr(0, sp), rest = trim(line.substr(sp));
		size_t name_end = rest.find_first_of(" \t=");
		std::string_view field_name = rest.substr(0, name_end);
		if (name_end != std::string_view::npos && trim(rest.substr(name_end)).rfind('=', 0) == 0)
			continue; // a constant
		if (field_name.empty())
			return fail("a field without a name");
		Ros2Field f;
		f.name = std::string(field_name);
		if (size_t open = type.find('['); open != std::string_view::npos) {
			if (type.back() != ']')
				return fail("an array type without its ']': '" + printable(type) + "'");
			std::string_view size = type.substr(open + 1, type.size() - open - 2);
			f.array = true;
			if (!size.empty() && size.rfind("<=", 0) != 0) { // (T[<=N]: a sequence)
				uint64_t n = 0;
				for (char c : size) {
					if (c < '0' || c > '9' || n > kMostFixed)
						return fail("an array size that is not a number: '" + printable(type) + "'");
					n = n * 10 + (uint64_t)(c - '0');
				}
				if (n == 0 || n > kMostFixed)
					return fail("an array size out of range: '" + printable(type) + "'");
				f.fixed = (uint32_t)n;
			}
			type = type.substr(0, open);
		}
		if (!primitive(type, &f.kind)) {
			if (type == "wstring" || type == "time" || type == "duration")
				return fail("type '" + printable(type) + "' is not supported");
			f.kind = Ros2Field::Kind::Nested;
			pending.push_back(Pending{ msg.types.size() - 1, msg.types.back().fields.size(), std::string(type), line_no });
		}
		msg.types.back().fields.push_back(std::move(f));
	}
	for (const Ros2Type &t : msg.types)
		if (t.fields.empty())
			return Error{ "type '" + printable(t.name) + "' has no fields" };
	// Nested types by name: in full ("pkg/Name"), or a bare name in the
	// package of the type that uses it.
	std::map<std::string, size_t> by_name;
	for (size_t i = 0; i < msg.types.size(); i++)
		by_name.emplace(msg.types[i].name, i);
	for (const Pending &p : pending) {
		std::string want = normal_name(p.name);
		if (want.find('/') == std::string::npos) {
			const std::string &owner = msg.types[p.type].name;
			if (size_t slash = owner.find('/'); slash != std::string::npos)
				want = owner.substr(0, slash + 1) + want;
		}
		auto it = by_name.find(want);
		if (it == by_name.end()) {
			line_no = p.line;
			return fail("type '" + printable(p.name) + "' is not defined");
		}
		msg.types[p.type].fields[p.field].nested = it->second;
	}
	return msg;
}

namespace {

class CdrReader {
public:
	explicit CdrReader(std::string_view body) : b_(body) {}

	Status read_type(const Ros2Msg &msg, size_t type, size_t depth, JsonValue *out)
	{
		if (depth > kMostDepth)
			return fail("types nested deeper than " + std::to_string(kMostDepth));
		out->type = JsonValue::Type::Object;
		for (const Ros2Field &f : msg.types[type].fields) {
			JsonValue v;
			Status s = f.array ? read_array(msg, f, depth, &v) : read_one(msg, f, depth, &v);
			if (!s)
				return s;
			out->object.emplace_back(f.name, std::move(v));
		}
		return Ok{};
	}

private:
	Status fail(const std::string &what) const { return Error{ "at byte " + std::to_string(pos_ + 4) + ": " + what }; }

	bool align(size_t n)
	{
		size_t to = (pos_ + n - 1) / n * n;
		if (to > b_.size())
			return false;
		pos_ = to;
		return true;
	}

	template <typename T>
	bool take(T *v)
	{
		if (!align(sizeof(T)) || b_.size() - pos_ < sizeof(T))
			return false;
		std::memcpy(v, b_.data() + pos_, sizeof(T));
		pos_ += sizeof(T);
		return true;
	}

	// A number; an integer type's keeps all its bits (but a uint64 past
	// int64's range, which JSON's integers do not hold).
	template <typename T>
	bool number(JsonValue *out)
	{
		T v;
		if (!take(&v))
			return false;
		out->type = JsonValue::Type::Number;
		out->number = (double)v;
		if constexpr (std::is_integral_v<T>) {
			out->is_integer = !std::is_same_v<T, uint64_t> || (uint64_t)v <= (uint64_t)INT64_MAX;
			out->integer = (int64_t)v;
		}
		return true;
	}

	Status read_one(const Ros2Msg &msg, const Ros2Field &f, size_t depth, JsonValue *out)
	{
		using K = Ros2Field::Kind;
		bool ok = false;
		switch (f.kind) {
		case K::Bool: {
			uint8_t v = 0;
			ok = take(&v);
			out->type = JsonValue::Type::Bool;
			out->boolean = v != 0;
			break;
		}
		case K::Int8: ok = number<int8_t>(out); break;
		case K::Uint8: ok = number<uint8_t>(out); break;
		case K::Int16: ok = number<int16_t>(out); break;
		case K::Uint16: ok = number<uint16_t>(out); break;
		case K::Int32: ok = number<int32_t>(out); break;
		case K::Uint32: ok = number<uint32_t>(out); break;
		case K::Int64: ok = number<int64_t>(out); break;
		case K::Uint64: ok = number<uint64_t>(out); break;
		case K::Float32: ok = number<float>(out); break;
		case K::Float64: ok = number<double>(out); break;
		case K::String: {
			uint32_t n;
			if (!take(&n))
				break;
			if (n > b_.size() - pos_)
				return fail("field '" + printable(f.name) + "': a string of " + std::to_string(n) + " bytes, " +
					    std::to_string(b_.size() - pos_) + " left");
			std::string_view s = b_.substr(pos_, n);
			pos_ += n;
			if (!s.empty() && s.back() == '\0') // (its count includes its NUL)
				s.remove_suffix(1);
			out->type = JsonValue::Type::String;
			out->string = std::string(s);
			ok = true;
			break;
		}
		case K::Nested:
			return read_type(msg, f.nested, depth + 1, out);
		}
		if (!ok)
			return fail("field '" + printable(f.name) + "': the message ends");
		return Ok{};
	}

	Status read_array(const Ros2Msg &msg, const Ros2Field &f, size_t depth, JsonValue *out)
	{
		uint32_t n = f.fixed;
		if (n == 0 && !take(&n))
			return fail("field '" + printable(f.name) + "': the message ends");
		// Every element takes at least a byte: more than the bytes left is a lie.
		if (n > b_.size() - pos_)
			return fail("field '" + printable(f.name) + "': " + std::to_string(n) + " elements, " +
				    std::to_string(b_.size() - pos_) + " bytes left");
		out->type = JsonValue::Type::Array;
		out->array.resize(n);
		Ros2Field one = f;
		one.array = false;
		for (uint32_t i = 0; i < n; i++)
			if (Status s = read_one(msg, one, depth, &out->array[i]); !s)
				return s;
		return Ok{};
	}

	std::string_view b_;
	size_t pos_ = 0;
};

} // namespace

Result<JsonValue> cdr_decode(const Ros2Msg &msg, std::string_view data)
{
	if (msg.types.empty())
		return Error{ "no message definition" };
	if (data.size() < 4)
		return Error{ "at byte 0: no CDR header" };
	if (data[0] != 0 || data[1] != 1)
		return Error{ "at byte 0: not little-endian CDR (encapsulation " + std::to_string((uint8_t)data[0]) + "," +
			      std::to_string((uint8_t)data[1]) + ")" };
	CdrReader r(data.substr(4));
	JsonValue v;
	if (Status s = r.read_type(msg, 0, 0, &v); !s)
		return s.error();
	return v;
}

} // namespace tcs
