// MessageDecoder: JSON parsed, CDR decoded by its schema's definition.
#include "message_decode.h"

#include "mcap_records.h"

namespace tcs {

Result<JsonValue> MessageDecoder::decode(const McapMessage &m)
{
	const std::string &encoding = m.channel->message_encoding;
	if (encoding == "json")
		return json_parse(m.data);
	if (encoding != "cdr")
		return Error{ "encoded as \"" + printable(encoding) + "\" (tcs reads json and cdr)" };
	if (!m.schema || m.schema->encoding != "ros2msg")
		return Error{ "cdr without a ros2msg schema" };
	auto it = schemas_.find(m.schema->id);
	if (it == schemas_.end() || it->second.text != m.schema->data) // (an id may be defined again)
		it = schemas_.insert_or_assign(m.schema->id, Parsed{ m.schema->data, ros2msg_parse(m.schema->name, m.schema->data) })
			     .first;
	if (!it->second.msg)
		return Error{ "its schema " + printable(m.schema->name) + ": " + it->second.msg.error().message };
	return cdr_decode(*it->second.msg, m.data);
}

} // namespace tcs
