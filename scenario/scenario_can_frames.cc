// Reading a [[can.frame]] table and its fields (see scenario_can_frames.h).
#include "scenario_can_frames.h"

#include <utility>

#include "scenario_can.h"
#include "scenario_drivers.h"
#include "scenario_units.h"

namespace tcs::scenario_parse {

namespace {

// A classic frame's payload, and CAN FD's.
constexpr int kClassicBytes = 8, kFdBytes = 64;

struct FieldType {
	const char *name;
	int bytes;
};
constexpr FieldType kFieldTypes[] = { { "int8", 1 },   { "int16", 2 },  { "int32", 4 },  { "uint8", 1 },
				      { "uint16", 2 }, { "uint32", 4 }, { "float32", 4 } };

int type_bytes(std::string_view type)
{
	for (const FieldType &t : kFieldTypes)
		if (type == t.name)
			return t.bytes;
	return 0;
}

std::string bytes_text(int start, int size)
{
	return size == 1 ? "byte " + std::to_string(start)
			 : "bytes " + std::to_string(start) + " to " + std::to_string(start + size - 1);
}

// A field's signal: any signal's value for a frame the world sends, an
// effort no one else drives for a command frame. A signal of several
// values needs the index of the one it carries.
Status read_field_signal(ScenarioReader &r, const Entry &e, bool command, CanFieldSpec *field)
{
	auto name = r.get_string(e, "\"pendulum.hinge.position\"");
	if (!name)
		return name.error();
	auto ix = split_signal_index(*name);
	if (!ix)
		return r.err(e.line, "signal '" + *name + "': an index is written [N], as in 'pendulum.rod.pose[2]'");
	const std::string base(ix->signal); // what the parts view
	auto parts = r.signal_parts(e.line, base);
	if (!parts)
		return parts.error();
	const int width = signal_field_width(parts->field);
	if (ix->index >= width)
		return r.err(e.line, "signal '" + *name + "': index " + std::to_string(ix->index) +
					     " is past the values of " + std::string(parts->field) + " (0 to " +
					     std::to_string(width - 1) + ")");
	// A joint's position, velocity and effort are one value but on a
	// universal joint, whose first axis [0] stands for.
	if (ix->index < 0 && width > 2)
		return r.err(e.line, "signal '" + *name + "' has " + std::to_string(width) +
					     " values and a field carries one: pick it, as '" + *name + "[0]'");
	if (command && parts->field != "effort")
		return r.err(e.line, "command frame field '" + *name + "' is not an effort: a command frame sets "
									 "<model>.<joint>.effort");
	if (command)
		if (auto other = effort_driver(r.sc, *name))
			return r.err(e.line, "signal '" + *name + "' is already driven by " + *other);
	field->signal = { *name, e.line };
	return Ok{};
}

// One field of `frame`, which holds the fields before it; *next is the
// byte after the previous one, where a field without `start` begins.
Status parse_field(ScenarioReader &r, const toml::table &t, const CanSpec &bus, CanFrameSpec &frame, int *next)
{
	CanFieldSpec f;
	f.line = line_of(t);
	if (Status s = r.check_keys(t, "in a field of [[can.frame]]", { "signal", "type", "scale", "offset", "start" }); !s)
		return s;
	auto es = entries(t);
	const Entry *signal = find_entry(es, "signal");
	const Entry *type = find_entry(es, "type");
	for (auto [entry, key] : { std::pair{ signal, "signal" }, { type, "type" } })
		if (!entry)
			return r.err(f.line, std::string("a field of [[can.frame]] needs '") + key + "'");
	if (Status s = read_field_signal(r, *signal, frame.command, &f); !s)
		return s;
	auto ty = r.get_string(*type, "\"int16\"");
	if (!ty)
		return ty.error();
	const int size = type_bytes(*ty);
	if (!size)
		return r.err(type->line, "type must be one of int8, int16, int32, uint8, uint16, uint32, float32, "
					 "not \"" + *ty + "\"");
	f.type = *ty;
	if (const Entry *e = find_entry(es, "scale")) {
		auto v = r.get_number(*e, "scale");
		if (!v)
			return v.error();
		if (*v == 0)
			return r.err(e->line, "scale must not be 0 (the value is the raw number times scale, plus offset)");
		f.scale = *v;
	}
	if (const Entry *e = find_entry(es, "offset")) {
		auto v = r.get_number(*e, "offset");
		if (!v)
			return v.error();
		f.offset = *v;
	}
	int64_t start = *next;
	const Entry *written = find_entry(es, "start");
	if (written) {
		auto v = r.get_integer(*written, "0");
		if (!v)
			return v.error();
		if (*v < 0)
			return r.err(written->line, "start must be a byte number >= 0");
		start = *v;
	}
	// Where the field's place is wrong: its start, else the field itself.
	const int where = written ? written->line : f.line;
	const int most = bus.data_bitrate ? kFdBytes : kClassicBytes;
	if (start > most - size)
		return r.err(where, "field '" + f.signal.name + "' (" + f.type + " at byte " + std::to_string(start) +
					     ") runs past the " + std::to_string(most) +
					     (bus.data_bitrate ? " bytes of a CAN FD frame"
							       : " bytes of a CAN frame (an interface with data_bitrate, "
								 "CAN FD, carries 64)"));
	f.start = (int)start;
	for (const CanFieldSpec &o : frame.fields) {
		const int o_size = type_bytes(o.type);
		if (f.start < o.start + o_size && o.start < f.start + size)
			return r.err(where, "field '" + f.signal.name + "' (" + bytes_text(f.start, size) +
						     ") overlaps field '" + o.signal.name + "' (" +
						     bytes_text(o.start, o_size) + ", line " + std::to_string(o.line) + ")");
	}
	*next = f.start + size;
	frame.fields.push_back(std::move(f));
	return Ok{};
}

Status parse_fields(ScenarioReader &r, const Entry &e, const CanSpec &bus, CanFrameSpec &frame)
{
	const toml::array *a = e.node->as_array();
	if (!a)
		return r.err(e.line, "fields must be an array of tables such as [ { signal = \"pendulum.hinge.position\", "
				     "type = \"int16\" } ], not " + std::string(type_name(*e.node)));
	if (a->empty() && frame.command)
		return r.err(e.line, "fields is empty: a command frame sets at least one effort");
	int next = 0;
	for (const toml::node &n : *a) {
		if (!n.is_table())
			return r.err(line_of(n), "fields must be tables such as { signal = \"pendulum.hinge.position\", "
						 "type = \"int16\" }, not " + std::string(type_name(n)));
		if (Status s = parse_field(r, *n.as_table(), bus, frame, &next); !s)
			return s;
	}
	return Ok{};
}

} // namespace

Status parse_can_frame(ScenarioReader &r, const toml::table &t, CanSpec &bus)
{
	CanFrameSpec f;
	f.line = line_of(t);
	if (Status s = r.check_keys(t, "in [[can.frame]]", { "id", "extended", "rate", "command", "byte_order", "fields" });
	    !s)
		return s;
	auto es = entries(t);
	const Entry *id = find_entry(es, "id");
	const Entry *order = find_entry(es, "byte_order");
	const Entry *fields = find_entry(es, "fields");
	for (auto [entry, key] : { std::pair{ id, "id" }, { order, "byte_order" }, { fields, "fields" } })
		if (!entry)
			return r.err(f.line, std::string("[[can.frame]] needs '") + key + "'");

	if (const Entry *e = find_entry(es, "extended")) {
		auto v = r.get_bool(*e);
		if (!v)
			return v.error();
		f.extended = *v;
	}
	auto v = read_can_id(r, *id, bus, f.extended, 0, f.extended ? "" : "; extended = true allows 29-bit ids");
	if (!v)
		return v.error();
	f.id = *v;

	const Entry *command = find_entry(es, "command");
	const Entry *rate = find_entry(es, "rate");
	if (command) {
		auto c = r.get_bool(*command);
		if (!c)
			return c.error();
		f.command = *c;
	}
	if (f.command && rate)
		return r.err(rate->line, "'rate' applies only to a frame the world sends: a command frame (command = "
					 "true) comes when the controller sends it");
	if (!f.command && !rate)
		return r.err(f.line, "[[can.frame]] needs a rate (a frame the world sends, such as rate = \"100Hz\") "
				     "or command = true (a frame the controller sends)");
	if (rate) {
		auto text = r.get_string(*rate, "\"100Hz\"");
		if (!text)
			return text.error();
		auto hz = parse_rate_hz(*text);
		if (!hz)
			return r.err(rate->line, "rate: " + hz.error().message);
		f.rate_hz = *hz;
		f.period_ns = rate_period_ns(*hz);
	}

	auto o = r.get_string(*order, "\"little\"");
	if (!o)
		return o.error();
	if (*o != "little" && *o != "big")
		return r.err(order->line, "byte_order must be \"little\" or \"big\", not \"" + *o + "\"");
	f.big_endian = *o == "big";

	// In place, so that effort_driver sees the fields read before each.
	bus.frames.push_back(std::move(f));
	return parse_fields(r, *fields, bus, bus.frames.back());
}

} // namespace tcs::scenario_parse
