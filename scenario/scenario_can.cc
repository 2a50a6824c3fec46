// Reading the [[can]] tables of a scenario and their motors (see
// scenario_can.h). Within a bus its motors and frames are read in file
// order, so that of two that clash the later is the one reported.
#include "scenario_can.h"

#include <algorithm>
#include <utility>

#include "scenario_can_frames.h"
#include "scenario_drivers.h"
#include "scenario_units.h"

namespace tcs::scenario_parse {

namespace {

// Classic CAN's bit rates (ISO 11898: 10 kbit/s to 1 Mbit/s); CAN FD's
// data phase goes to 8 Mbit/s on the transceivers sold for it.
constexpr int64_t kMinBitrate = 10000, kMaxBitrate = 1000000, kMaxDataBitrate = 8000000;
constexpr uint32_t kMaxStandardId = 0x7FF, kMaxExtendedId = 0x1FFFFFFF;

std::string bitrate_text(int64_t bps)
{
	if (bps % 1000000 == 0)
		return std::to_string(bps / 1000000) + " Mbit/s";
	if (bps % 1000 == 0)
		return std::to_string(bps / 1000) + " kbit/s";
	return std::to_string(bps) + " bit/s";
}

// A bit rate written "1Mbit/s" or 1000000 (bit/s), within [lo, hi].
Result<int64_t> read_bitrate(const ScenarioReader &r, const Entry &e, int64_t lo, int64_t hi, const std::string &range)
{
	int64_t bps;
	std::string shown;
	if (e.node->is_integer()) {
		bps = e.node->as_integer()->get();
		shown = std::to_string(bps);
	} else if (e.node->is_string()) {
		auto text = r.get_string(e, "\"1Mbit/s\"");
		if (!text)
			return text.error();
		auto v = parse_bitrate(*text);
		if (!v)
			return r.err(e.line, e.key + ": " + v.error().message);
		bps = *v;
		shown = "'" + *text + "'";
	} else {
		return r.err(e.line, e.key + " must be a string such as \"1Mbit/s\" or an integer (bit/s), not " +
					     type_name(*e.node));
	}
	if (bps < lo || bps > hi)
		return r.err(e.line, e.key + " " + shown + " is out of range (" + range + ")");
	return bps;
}

Status parse_motor(ScenarioReader &r, const toml::table &t, CanSpec &bus)
{
	CanMotorSpec m;
	m.line = line_of(t);
	if (Status s = r.check_keys(t, "in [[can.motor]]",
				  { "protocol", "id", "reply_id", "joint", "position_range", "velocity_range",
				    "torque_range", "kp_max", "kd_max" });
	    !s)
		return s;
	auto es = entries(t);
	const Entry *protocol = find_entry(es, "protocol");
	const Entry *id = find_entry(es, "id");
	const Entry *joint = find_entry(es, "joint");
	for (auto [entry, key] : { std::pair{ protocol, "protocol" }, { id, "id" }, { joint, "joint" } })
		if (!entry)
			return r.err(m.line, std::string("[[can.motor]] needs '") + key + "'");

	auto p = r.get_string(*protocol, "\"mit\"");
	if (!p)
		return p.error();
	if (*p != "mit")
		return r.err(protocol->line, "unknown protocol '" + *p + "' (known: mit)");
	m.protocol = *p;

	auto v = read_can_id(r, *id, bus, false, 1, "");
	if (!v)
		return v.error();
	m.id = *v;
	if (const Entry *reply = find_entry(es, "reply_id")) {
		auto n = r.get_integer(*reply, "0");
		if (!n)
			return n.error();
		if (*n < 0 || *n > kMaxStandardId)
			return r.err(reply->line, "reply_id " + (*n < 0 ? std::to_string(*n) : hex((uint64_t)*n, 3)) +
							  " is out of range (0x000 to 0x7FF)");
		m.reply_id = (uint32_t)*n;
	}

	auto name = r.get_string(*joint, "\"pendulum.hinge\"");
	if (!name)
		return name.error();
	if (auto parts = r.part_name(joint->line, "joint", *name); !parts)
		return parts.error();
	if (auto other = effort_driver(r.sc, *name + ".effort"))
		return r.err(joint->line, "joint '" + *name + "' is already driven by " + *other);
	m.joint = { *name, joint->line };

	// The ranges map the protocol's fixed-point fields onto physical
	// values: each is the magnitude of the field's extreme.
	for (auto [key, out] : { std::pair{ "position_range", &m.position_range }, { "velocity_range", &m.velocity_range },
				 { "torque_range", &m.torque_range }, { "kp_max", &m.kp_max }, { "kd_max", &m.kd_max } }) {
		const Entry *e = find_entry(es, key);
		if (!e)
			continue;
		auto x = r.get_number(*e, key);
		if (!x)
			return x.error();
		if (*x <= 0)
			return r.err(e->line, std::string(key) + " must be positive (the magnitude the protocol's "
								 "field reaches at its extreme)");
		*out = *x;
	}
	bus.motors.push_back(std::move(m));
	return Ok{};
}

Status parse_can(ScenarioReader &r, const toml::table &t)
{
	CanSpec c;
	c.line = line_of(t);
	if (Status s = r.check_keys(t, "in [[can]]", { "interface", "bitrate", "data_bitrate", "motor", "frame" }); !s)
		return s;
	auto es = entries(t);
	const Entry *interface = find_entry(es, "interface");
	const Entry *bitrate = find_entry(es, "bitrate");
	for (auto [entry, key] : { std::pair{ interface, "interface" }, { bitrate, "bitrate" } })
		if (!entry)
			return r.err(c.line, std::string("[[can]] needs '") + key + "'");

	auto name = r.get_string(*interface, "\"can0\"");
	if (!name)
		return name.error();
	if (!is_interface_name(*name))
		return r.err(interface->line, "interface '" + *name + "' is not a network interface's name (1 to "
									"15 of A-Z a-z 0-9 _ . -)");
	for (const CanSpec &o : r.sc.cans)
		if (o.interface == *name)
			return r.err(interface->line, "interface '" + *name + "' is already declared at line " +
							      std::to_string(o.line));
	c.interface = *name;

	auto bps = read_bitrate(r, *bitrate, kMinBitrate, kMaxBitrate, "10 kbit/s to 1 Mbit/s");
	if (!bps)
		return bps.error();
	c.bitrate = *bps;
	if (const Entry *data = find_entry(es, "data_bitrate")) {
		auto d = read_bitrate(r, *data, 1, kMaxDataBitrate, "at most 8 Mbit/s, CAN FD's");
		if (!d)
			return d.error();
		if (*d < c.bitrate)
			return r.err(data->line, "data_bitrate (" + bitrate_text(*d) + ") is below bitrate (" +
							 bitrate_text(c.bitrate) +
							 "): CAN FD's data phase is at least as fast as its arbitration");
		c.data_bitrate = *d;
	}

	r.sc.cans.push_back(std::move(c));
	CanSpec &bus = r.sc.cans.back();
	auto motors = r.table_array(t, "motor", "can.motor");
	if (!motors)
		return motors.error();
	auto frames = r.table_array(t, "frame", "can.frame");
	if (!frames)
		return frames.error();
	std::vector<std::pair<const toml::table *, bool>> parts; // (table, is a frame)
	for (const toml::table *m : *motors)
		parts.push_back({ m, false });
	for (const toml::table *f : *frames)
		parts.push_back({ f, true });
	std::stable_sort(parts.begin(), parts.end(),
			 [](const auto &a, const auto &b) { return line_of(*a.first) < line_of(*b.first); });
	for (auto [table, frame] : parts)
		if (Status s = frame ? parse_can_frame(r, *table, bus) : parse_motor(r, *table, bus); !s)
			return s;
	return Ok{};
}

} // namespace

Result<uint32_t> read_can_id(const ScenarioReader &r, const Entry &e, const CanSpec &bus, bool extended,
			     uint32_t least, const std::string &hint)
{
	const int digits = extended ? 8 : 3;
	auto v = r.get_integer(e, "0x100");
	if (!v)
		return v.error();
	const int64_t most = extended ? kMaxExtendedId : kMaxStandardId;
	if (*v < least || *v > most)
		return r.err(e.line, e.key + " " + (*v < 0 ? std::to_string(*v) : hex((uint64_t)*v, digits)) +
					     " is out of range (" + hex(least, digits) + " to " + hex(most, digits) + hint + ")");
	const uint32_t id = (uint32_t)*v;
	for (const CanMotorSpec &m : bus.motors)
		if (!extended && m.id == id)
			return r.err(e.line, "CAN id " + hex(id, digits) + " is already used on " + bus.interface +
						     " by the motor at line " + std::to_string(m.line));
	for (const CanFrameSpec &f : bus.frames)
		if (f.extended == extended && f.id == id)
			return r.err(e.line, "CAN id " + hex(id, digits) + " is already used on " + bus.interface +
						     " by the frame at line " + std::to_string(f.line));
	return id;
}

Status parse_cans(const toml::table &root, ScenarioReader &r)
{
	auto tables = r.table_array(root, "can");
	if (!tables)
		return tables.error();
	for (const toml::table *t : *tables)
		if (Status s = parse_can(r, *t); !s)
			return s;
	return Ok{};
}

} // namespace tcs::scenario_parse
