// JSON written: strings escaped (any bytes in, valid JSON out) and whole
// values (tcs-trace's export of decoded messages).
#include "json_write.h"

#include "json.h"
#include "utf8.h"

#include <charconv>
#include <cmath>

namespace tcs {

void json_append_string(std::string &out, std::string_view text)
{
	static const char hex[] = "0123456789abcdef";
	out += '"';
	for (size_t i = 0; i < text.size();) {
		const uint8_t c = uint8_t(text[i]);
		if (c == '"' || c == '\\') {
			out += '\\';
			out += char(c);
		} else if (c >= 0x20 && c < 0x80) {
			out += char(c);
		} else if (c == '\n') {
			out += "\\n";
		} else if (c == '\t') {
			out += "\\t";
		} else if (c == '\r') {
			out += "\\r";
		} else if (c == '\b') {
			out += "\\b";
		} else if (c == '\f') {
			out += "\\f";
		} else if (c < 0x20) {
			out += "\\u00";
			out += hex[c >> 4];
			out += hex[c & 15];
		} else {
			// Bytes that are not UTF-8 would make the whole text
			// unreadable to a JSON parser: each becomes U+FFFD.
			const size_t n = utf8_length(text, i);
			if (n == 0) {
				out += "\\ufffd";
				i++;
			} else {
				out.append(text, i, n);
				i += n;
			}
			continue;
		}
		i++;
	}
	out += '"';
}

void json_append(std::string &out, const JsonValue &v)
{
	char buf[32];
	switch (v.type) {
	case JsonValue::Type::Null:
		out += "null";
		return;
	case JsonValue::Type::Bool:
		out += v.boolean ? "true" : "false";
		return;
	case JsonValue::Type::Number:
		if (v.is_integer)
			out.append(buf, (size_t)(std::to_chars(buf, buf + sizeof buf, v.integer).ptr - buf));
		else if (std::isfinite(v.number))
			out.append(buf, (size_t)(std::to_chars(buf, buf + sizeof buf, v.number).ptr - buf));
		else
			out += "null";
		return;
	case JsonValue::Type::String:
		json_append_string(out, v.string);
		return;
	case JsonValue::Type::Array:
		out += '[';
		for (size_t i = 0; i < v.array.size(); i++) {
			if (i)
				out += ',';
			json_append(out, v.array[i]);
		}
		out += ']';
		return;
	case JsonValue::Type::Object:
		out += '{';
		for (size_t i = 0; i < v.object.size(); i++) {
			if (i)
				out += ',';
			json_append_string(out, v.object[i].first);
			out += ':';
			json_append(out, v.object[i].second);
		}
		out += '}';
		return;
	}
}

} // namespace tcs
