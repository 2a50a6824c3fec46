// print_signals(): tcs-run --list-signals.
#include "list_signals.h"

#include <cstdio>

namespace tcs {

// The scenario's wires, for --list-signals: each bus and what is on it.
static void print_wires(const WiresConfig &w)
{
	if (w.serials.empty() && w.i2cs.empty() && w.cans.empty())
		return;
	printf("wires\n");
	for (const SerialSpec &s : w.serials) {
		printf("  %-28s serial   %lld baud\n", s.path.c_str(), (long long)s.baud);
		for (const ServoSpec &v : s.servos)
			printf("    servo %-3u %-12s %s\n", v.id, v.protocol.c_str(), v.joint.name.c_str());
	}
	for (const I2cSpec &b : w.i2cs) {
		printf("  %-28s i2c      %lld Hz\n", ("/dev/i2c-" + std::to_string(b.bus)).c_str(), (long long)b.clock_hz);
		for (const I2cDeviceSpec &d : b.devices)
			printf("    0x%02x  %-12s %s\n", d.address, d.chip.c_str(), d.link.name.c_str());
	}
	for (const CanSpec &c : w.cans) {
		printf("  %-28s can      %lld bit/s%s\n", c.interface.c_str(), (long long)c.bitrate,
		       c.data_bitrate ? (", FD data " + std::to_string(c.data_bitrate) + " bit/s").c_str() : "");
		for (const CanMotorSpec &m : c.motors)
			printf("    motor 0x%03x %-10s %s\n", m.id, m.protocol.c_str(), m.joint.name.c_str());
		for (const CanFrameSpec &f : c.frames)
			printf("    frame 0x%03x %s, %zu fields\n", f.id, f.command ? "command" : "sensor", f.fields.size());
	}
}

void print_signals(const std::string &world_file, const WorldSetup &setup)
{
	printf("%s: signals\n", world_file.empty() ? "built-in scenario" : world_file.c_str());
	for (const auto &line : setup.signal_lines)
		printf("  %s\n", line.c_str());
	printf("devices\n");
	for (const auto &d : setup.devices) {
		if (is_wire(d.kind))
			continue;
		std::string sigs;
		for (const auto &sig : d.signals)
			sigs += (sigs.empty() ? "" : " ") + sig;
		printf("  %-28s %-8s %-6s %s%s\n", d.path.c_str(),
		       d.kind == TCS_DEVICE_SENSOR ? "sensor" : "actuator",
		       d.format == TCS_FORMAT_TEXT ? "text" : "binary",
		       d.kind == TCS_DEVICE_ACTUATOR ? "" : d.latest ? "latest " : "stream ", sigs.c_str());
	}
	print_wires(setup.wires);
}

} // namespace tcs
