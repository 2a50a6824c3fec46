// Reading the [[i2c]] tables of a scenario and their chips (see
// scenario_i2c.h).
#include "scenario_i2c.h"

#include <tuple>
#include <utility>

#include "scenario_units.h"

namespace tcs::scenario_parse {

namespace {

// From a slow SMBus's 10 kHz to high-speed mode's 3.4 MHz.
constexpr int64_t kMinClockHz = 10000, kMaxClockHz = 3400000;
constexpr int64_t kMaxBus = 255;
// 7-bit addresses less the reserved ones (general call, CBUS, 10-bit...).
constexpr int64_t kMinAddress = 0x03, kMaxAddress = 0x77;
// An MPU-6050 answers at 0x68, or 0x69 with its AD0 pin high.
constexpr int64_t kMpu6050Address = 0x68;

std::string bus_path(int bus)
{
	return "/dev/i2c-" + std::to_string(bus);
}

// A clock written "400kHz" or 400000 (Hz).
Result<int64_t> read_clock(const ScenarioReader &r, const Entry &e)
{
	int64_t hz;
	std::string shown;
	if (e.node->is_integer()) {
		hz = e.node->as_integer()->get();
		shown = std::to_string(hz);
	} else if (e.node->is_string()) {
		auto text = r.get_string(e, "\"400kHz\"");
		if (!text)
			return text.error();
		auto v = parse_clock_hz(*text);
		if (!v)
			return r.err(e.line, "clock: " + v.error().message);
		hz = *v;
		shown = "'" + *text + "'";
	} else {
		return r.err(e.line, "clock must be a string such as \"400kHz\" or an integer (Hz), not " +
					     std::string(type_name(*e.node)));
	}
	if (hz < kMinClockHz || hz > kMaxClockHz)
		return r.err(e.line, "clock " + shown + " is out of range (10 kHz to 3.4 MHz)");
	return hz;
}

Result<double> read_noise(const ScenarioReader &r, const Entry &e, const char *unit)
{
	auto v = r.get_number(e, e.key);
	if (!v)
		return v.error();
	if (*v < 0)
		return r.err(e.line, e.key + " must be a standard deviation >= 0, in " + unit);
	return *v;
}

Status parse_chip(ScenarioReader &r, const toml::table &t, I2cSpec &bus)
{
	I2cDeviceSpec d;
	d.line = line_of(t);
	if (Status s = r.check_keys(t, "in [[i2c.device]]", { "address", "chip", "link", "accel_noise", "gyro_noise" });
	    !s)
		return s;
	auto es = entries(t);
	const Entry *address = find_entry(es, "address");
	const Entry *chip = find_entry(es, "chip");
	const Entry *link = find_entry(es, "link");
	for (auto [entry, key] : { std::pair{ address, "address" }, { chip, "chip" }, { link, "link" } })
		if (!entry)
			return r.err(d.line, std::string("[[i2c.device]] needs '") + key + "'");

	auto a = r.get_integer(*address, "0x68");
	if (!a)
		return a.error();
	if (*a < kMinAddress || *a > kMaxAddress)
		return r.err(address->line, "address " + (*a < 0 ? std::to_string(*a) : hex((uint64_t)*a, 2)) +
						    " is out of range (0x03 to 0x77, the 7-bit addresses not reserved)");
	for (const I2cDeviceSpec &o : bus.devices)
		if (o.address == (uint32_t)*a)
			return r.err(address->line, "address " + hex((uint64_t)*a, 2) + " is already used on " +
							    bus_path(bus.bus) + " at line " + std::to_string(o.line));
	d.address = (uint32_t)*a;

	auto c = r.get_string(*chip, "\"mpu6050\"");
	if (!c)
		return c.error();
	if (*c != "mpu6050")
		return r.err(chip->line, "unknown chip '" + *c + "' (known: mpu6050)");
	d.chip = *c;
	if (d.address != kMpu6050Address && d.address != kMpu6050Address + 1)
		return r.err(address->line, "an mpu6050 answers at 0x68 or 0x69 (its AD0 pin), not " +
						    hex(d.address, 2));

	auto name = r.get_string(*link, "\"pendulum.rod\"");
	if (!name)
		return name.error();
	if (auto parts = r.part_name(link->line, "link", *name); !parts)
		return parts.error();
	d.link = { *name, link->line };

	for (auto [key, out, unit] : { std::tuple{ "accel_noise", &d.accel_noise, "m/s\xc2\xb2" },
				       { "gyro_noise", &d.gyro_noise, "rad/s" } }) {
		const Entry *e = find_entry(es, key);
		if (!e)
			continue;
		auto v = read_noise(r, *e, unit);
		if (!v)
			return v.error();
		*out = *v;
	}
	bus.devices.push_back(std::move(d));
	return Ok{};
}

Status parse_i2c(ScenarioReader &r, const toml::table &t)
{
	I2cSpec b;
	b.line = line_of(t);
	if (Status s = r.check_keys(t, "in [[i2c]]", { "bus", "clock", "device" }); !s)
		return s;
	auto es = entries(t);
	const Entry *bus = find_entry(es, "bus");
	if (!bus)
		return r.err(b.line, "[[i2c]] needs 'bus' (N of /dev/i2c-N)");
	auto n = r.get_integer(*bus, "1");
	if (!n)
		return n.error();
	if (*n < 0 || *n > kMaxBus)
		return r.err(bus->line, "bus " + std::to_string(*n) + " is out of range (0 to 255)");
	b.bus = (int)*n;
	for (const I2cSpec &o : r.sc.i2cs)
		if (o.bus == b.bus)
			return r.err(bus->line, "bus " + std::to_string(b.bus) + " is already declared at line " +
							std::to_string(o.line));
	// Its device file is a path like any device's: one owner.
	const std::string path = bus_path(b.bus);
	for (const DeviceSpec &d : r.sc.devices)
		if (d.path == path)
			return r.err(bus->line, path + " is already the [[device]] at line " + std::to_string(d.line));
	for (const SerialSpec &s : r.sc.serials)
		if (s.path == path)
			return r.err(bus->line, path + " is already the [[serial]] at line " + std::to_string(s.line));

	if (const Entry *clock = find_entry(es, "clock")) {
		auto hz = read_clock(r, *clock);
		if (!hz)
			return hz.error();
		b.clock_hz = *hz;
	}

	r.sc.i2cs.push_back(std::move(b));
	auto devices = r.table_array(t, "device", "i2c.device");
	if (!devices)
		return devices.error();
	for (const toml::table *d : *devices)
		if (Status s = parse_chip(r, *d, r.sc.i2cs.back()); !s)
			return s;
	return Ok{};
}

} // namespace

Status parse_i2cs(const toml::table &root, ScenarioReader &r)
{
	auto tables = r.table_array(root, "i2c");
	if (!tables)
		return tables.error();
	for (const toml::table *t : *tables)
		if (Status s = parse_i2c(r, *t); !s)
			return s;
	return Ok{};
}

} // namespace tcs::scenario_parse
