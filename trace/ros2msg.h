// ROS 2 message definitions (MCAP's "ros2msg" schema encoding) and CDR
// messages decoded by them into JSON values, so that every reader of a trace
// sees one shape of message whatever its channel's encoding. Both are
// untrusted input: a definition may name types it does not define or nest
// them without end, a message may be short or claim a billion elements;
// each is an error naming what is wrong, never a read past the bytes.
//
// The subset tcs and ROS 2 bags use: the primitive types, string (bounded
// or not), nested types (MSG: sections), and arrays of any of them (T[],
// T[N], T[<=N]); constants and default values are read past.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "error.h"
#include "json.h"

namespace tcs {

struct Ros2Field {
	enum class Kind : uint8_t { Bool, Int8, Uint8, Int16, Uint16, Int32, Uint32, Int64, Uint64, Float32, Float64, String, Nested };
	std::string name;
	Kind kind = Kind::Int32;
	size_t nested = 0;  // Nested: its index in Ros2Msg::types
	bool array = false;
	uint32_t fixed = 0; // an array of exactly this many (0: a sequence, its count first)
};

struct Ros2Type {
	std::string name; // "pkg/Name"
	std::vector<Ros2Field> fields;
};

struct Ros2Msg {
	std::vector<Ros2Type> types; // types[0]: the message itself
};

// Errors: "line N: what is wrong" (counted over the whole text).
Result<Ros2Msg> ros2msg_parse(std::string_view name, std::string_view text);

// A CDR message (XCDR1, little-endian: its 4-byte encapsulation header
// first) as a JSON object of its fields in order. Errors: "at byte N: ...".
Result<JsonValue> cdr_decode(const Ros2Msg &msg, std::string_view data);

} // namespace tcs
