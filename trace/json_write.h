// JSON text written: strings escaped, whole values (json.h's JsonValue).
#pragma once

#include <string>
#include <string_view>

namespace tcs {

struct JsonValue;

// Appends text to out as a JSON string literal (quotes included).
void json_append_string(std::string &out, std::string_view text);

// Appends v to out as JSON text (a number that is not finite as null).
void json_append(std::string &out, const JsonValue &v);

} // namespace tcs
