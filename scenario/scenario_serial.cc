// Reading the [[serial]] tables of a scenario and their servos (see
// scenario_serial.h).
#include "scenario_serial.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include "scenario_drivers.h"
#include "scenario_units.h"

namespace tcs::scenario_parse {

namespace {

// termios's named rates below 300 (B50 ... B200); from 300 on any rate is
// one BOTHER can set, up to what USB serial adapters reach.
constexpr int64_t kLowRates[] = { 50, 75, 110, 134, 150, 200 };
constexpr int64_t kMinAnyBaud = 300, kMaxBaud = 4000000;
// Protocol 2.0: 253 is reserved, 254 the broadcast id.
constexpr int64_t kMaxServoId = 252;

// What an X-series servo's Baud Rate (8) can be set to, within kMaxBaud.
constexpr int64_t kServoRates[] = { 9600, 57600, 115200, 1000000, 2000000, 3000000, 4000000 };

bool is_baud(int64_t b)
{
	for (int64_t low : kLowRates)
		if (b == low)
			return true;
	return b >= kMinAnyBaud && b <= kMaxBaud;
}

Status parse_servo(ScenarioReader &r, const toml::table &t, SerialSpec &line)
{
	ServoSpec v;
	v.line = line_of(t);
	if (Status s = r.check_keys(t, "in [[serial.servo]]", { "protocol", "id", "joint" }); !s)
		return s;
	auto es = entries(t);
	const Entry *protocol = find_entry(es, "protocol");
	const Entry *id = find_entry(es, "id");
	const Entry *joint = find_entry(es, "joint");
	for (auto [entry, key] : { std::pair{ protocol, "protocol" }, { id, "id" }, { joint, "joint" } })
		if (!entry)
			return r.err(v.line, std::string("[[serial.servo]] needs '") + key + "'");

	auto p = r.get_string(*protocol, "\"dynamixel2\"");
	if (!p)
		return p.error();
	if (*p != "dynamixel2")
		return r.err(protocol->line, "unknown protocol '" + *p + "' (known: dynamixel2)");
	v.protocol = *p;

	auto n = r.get_integer(*id, "1");
	if (!n)
		return n.error();
	if (*n < 0 || *n > kMaxServoId)
		return r.err(id->line, "id " + std::to_string(*n) + " is out of range (0 to 252; 253 is reserved and "
									"254 the broadcast id)");
	for (const ServoSpec &o : line.servos)
		if (o.id == (uint32_t)*n)
			return r.err(id->line, "servo id " + std::to_string(*n) + " is already used on " + line.path +
						       " at line " + std::to_string(o.line));
	v.id = (uint32_t)*n;

	auto name = r.get_string(*joint, "\"pendulum.hinge\"");
	if (!name)
		return name.error();
	if (auto parts = r.part_name(joint->line, "joint", *name); !parts)
		return parts.error();
	if (auto other = effort_driver(r.sc, *name + ".effort"))
		return r.err(joint->line, "joint '" + *name + "' is already driven by " + *other);
	v.joint = { *name, joint->line };
	line.servos.push_back(std::move(v));
	return Ok{};
}

Status parse_serial(ScenarioReader &r, const toml::table &t)
{
	SerialSpec s;
	s.line = line_of(t);
	if (Status st = r.check_keys(t, "in [[serial]]", { "path", "baud", "servo" }); !st)
		return st;
	auto es = entries(t);
	const Entry *path = find_entry(es, "path");
	const Entry *baud = find_entry(es, "baud");
	for (auto [entry, key] : { std::pair{ path, "path" }, { baud, "baud" } })
		if (!entry)
			return r.err(s.line, std::string("[[serial]] needs '") + key + "'");

	auto p = r.get_string(*path, "\"/dev/ttyUSB0\"");
	if (!p)
		return p.error();
	if (!is_normal_absolute_path(*p))
		return r.err(path->line, "serial path '" + *p + "' must be absolute and normal (no '.', '..', '//' "
								"or trailing '/')");
	for (const DeviceSpec &d : r.sc.devices)
		if (d.path == *p)
			return r.err(path->line, "path '" + *p + "' is already the [[device]] at line " +
							 std::to_string(d.line));
	for (const SerialSpec &o : r.sc.serials)
		if (o.path == *p)
			return r.err(path->line, "path '" + *p + "' is already the [[serial]] at line " +
							 std::to_string(o.line));
	s.path = *p;

	auto b = r.get_integer(*baud, "57600");
	if (!b)
		return b.error();
	if (!is_baud(*b))
		return r.err(baud->line, "baud " + std::to_string(*b) + " is not a rate a serial line takes (50, 75, "
									"110, 134, 150, 200, or 300 to 4000000)");
	s.baud = *b;

	r.sc.serials.push_back(std::move(s));
	auto servos = r.table_array(t, "servo", "serial.servo");
	if (!servos)
		return servos.error();
	for (const toml::table *v : *servos)
		if (Status st = parse_servo(r, *v, r.sc.serials.back()); !st)
			return st;
	// Servos on the line: its rate must be one they take.
	if (!r.sc.serials.back().servos.empty() &&
	    std::find(std::begin(kServoRates), std::end(kServoRates), *b) == std::end(kServoRates))
		return r.err(baud->line, "baud " + std::to_string(*b) + " is not a rate of a Dynamixel X servo (9600, "
									"57600, 115200, 1000000, 2000000, 3000000 or 4000000)");
	return Ok{};
}

} // namespace

Status parse_serials(const toml::table &root, ScenarioReader &r)
{
	auto tables = r.table_array(root, "serial");
	if (!tables)
		return tables.error();
	for (const toml::table *t : *tables)
		if (Status s = parse_serial(r, *t); !s)
			return s;
	return Ok{};
}

} // namespace tcs::scenario_parse
