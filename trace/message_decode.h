// MessageDecoder: a trace's message as a JSON value, whatever its channel's
// encoding (json, or cdr with a ros2msg schema), for the readers of traces
// (tcs-trace, replay). Each schema is parsed once.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "error.h"
#include "json.h"
#include "mcap_reader.h"
#include "ros2msg.h"

namespace tcs {

class MessageDecoder {
public:
	// Errors name what is wrong, not where: the caller knows the topic
	// and the message's number.
	Result<JsonValue> decode(const McapMessage &m);

private:
	struct Parsed {
		std::string text; // the definition it was parsed from
		Result<Ros2Msg> msg;
	};
	std::map<uint16_t, Parsed> schemas_;
};

} // namespace tcs
