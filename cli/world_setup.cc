// world_setup(): build the world once to validate it, and describe it.
#include "world_setup.h"

#include <cstdio>

namespace tcs {

// The wires, each a device in the table (after the others, in the order
// the coordinator's Wires binds them: serial lines, I2C buses, CAN
// interfaces), and their buses for the coordinator. Every CAN interface
// is on the one bus after the others (its socket may bind to any).
static void add_wires(const Scenario &sc, WorldSetup &out)
{
	out.wires.scenario_file = sc.file;
	out.wires.serials = sc.serials;
	out.wires.i2cs = sc.i2cs;
	out.wires.cans = sc.cans;
	size_t index = 0;
	auto add = [&](const std::string &path, int kind, uint32_t width) {
		DeviceConfig dc;
		dc.path = path;
		dc.kind = kind;
		dc.wire = index++;
		dc.table_width = width;
		out.devices.push_back(std::move(dc));
	};
	for (const SerialSpec &s : sc.serials)
		add(s.path, TCS_DEVICE_SERIAL, uint32_t(s.baud));
	for (const I2cSpec &b : sc.i2cs)
		add("/dev/i2c-" + std::to_string(b.bus), TCS_DEVICE_I2C, 0);
	const size_t can_bus = index;
	for (const CanSpec &c : sc.cans) {
		add(c.interface, TCS_DEVICE_CAN, c.data_bitrate > 0 ? 72 : 16);
		out.devices.back().wire = can_bus;
	}
}

Result<WorldSetup> world_setup(const Scenario &sc)
{
	WorldSetup out;
	out.step_ns = sc.sim.step_ns;
	for (const auto &m : sc.models) {
		ModelInstance mi{ m.name, m.type, {} };
		for (const auto &p : m.params)
			mi.params.emplace_back(p.key, p.value);
		out.models.push_back(std::move(mi));
	}
	auto world = SimWorld::create(out.models, out.step_ns);
	if (!world) {
		// A robot file's own mistake is at its own line ("FILE:LINE: ...").
		// Otherwise: point at the model the plug-in complained about.
		int line = sc.models.empty() ? 0 : sc.models.front().line;
		const std::string &msg = world.error().message;
		for (const auto &m : sc.models)
			if (msg.rfind(m.type + ":", 0) == 0)
				return world.error();
		for (const auto &m : sc.models) {
			if (msg.find(m.name) == std::string::npos && msg.find(m.type) == std::string::npos)
				continue;
			line = m.line;
			// Or at the parameter it names: a robot file's placement by its
			// table's name (pose) or a joint's (initial_position.<joint>).
			for (const auto &p : m.params) {
				const size_t dot = p.key.find('.');
				for (const std::string &name : { p.key, p.key.substr(0, dot), dot == std::string::npos ? "" : p.key.substr(dot + 1) })
					if (!name.empty() && msg.find("'" + name + "'") != std::string::npos) {
						line = p.line;
						break;
					}
			}
			break;
		}
		return scenario_error(sc, line, world.error().message);
	}
	// A scenario without a step of its own takes its world file's (10 us
	// to 1 s, as a scenario's).
	const int64_t asked = (*world)->file_step_ns();
	if (!sc.sim.step_given && asked >= 10000 && asked <= 1000000000 && asked != out.step_ns) {
		out.step_ns = asked;
		world = SimWorld::create(out.models, out.step_ns);
		if (!world)
			return scenario_error(sc, sc.models.front().line, world.error().message);
	}
	std::vector<std::string> known;
	for (size_t i = 0; i < (*world)->signal_count(); i++) {
		const tcs_sim_signal_info &s = (*world)->signal(i);
		known.push_back(s.name);
		std::string name = s.name;
		const std::string pos = ".position";
		if (s.width == 1 && name.size() > pos.size() && name.compare(name.size() - pos.size(), pos.size(), pos) == 0)
			out.joints.push_back(name.substr(0, name.size() - pos.size()));
		// A sensor's rate (its file's, or its [[sensor]]'s), then whether
		// a sensor model is on it.
		double hz = s.rate_hz;
		const SensorModelSpec *model = nullptr;
		for (const auto &sm : sc.sensors)
			if (sm.signal.name == s.name) {
				model = &sm;
				hz = sm.rate_hz > 0 ? sm.rate_hz : hz;
			}
		char rate[64] = "";
		if (hz > 0)
			snprintf(rate, sizeof rate, "%g Hz", hz);
		char line[512];
		snprintf(line, sizeof line, "%-36s %u value%s  %-10s %-9s %s%s", s.name, s.width, s.width == 1 ? " " : "s",
			 s.unit ? s.unit : "", (s.flags & TCS_SIM_SIGNAL_WRITABLE) ? "writable" : "", rate,
			 model ? (std::string(hz > 0 ? ", " : "") + "sensor model (line " + std::to_string(model->line) + ")").c_str()
			       : "");
		std::string text = line;
		text.erase(text.find_last_not_of(' ') + 1);
		out.signal_lines.push_back(text);
	}
	if (auto st = check_signals(sc, known); !st)
		return st.error();
	for (const auto &sm : sc.sensors)
		out.sensors.push_back({ sm.signal.name, sm.noise, sm.bias, sm.resolution, sm.latency_ns, sm.rate_hz });
	if (auto st = (*world)->sense(out.sensors, 1); !st)
		return st.error();
	for (const auto &d : sc.devices) {
		DeviceConfig dc;
		dc.path = d.path;
		dc.kind = d.kind == DeviceSpec::Kind::Sensor ? TCS_DEVICE_SENSOR : TCS_DEVICE_ACTUATOR;
		dc.format = d.format == DeviceSpec::Format::Text ? TCS_FORMAT_TEXT : TCS_FORMAT_BINARY;
		dc.latest = d.mode == DeviceSpec::Mode::Latest;
		dc.period_ns = d.period_ns;
		dc.limit = d.limit;
		for (const auto &s : d.signals) {
			long i = (*world)->find(s.name);
			if (d.kind == DeviceSpec::Kind::Actuator && i >= 0 &&
			    !((*world)->signal((size_t)i).flags & TCS_SIM_SIGNAL_WRITABLE))
				return scenario_error(sc, s.line, "signal '" + s.name + "' cannot be commanded");
			dc.signals.push_back(s.name);
		}
		out.devices.push_back(std::move(dc));
	}
	if (out.devices.size() > TCS_MAX_DEVICES)
		return scenario_error(sc, sc.devices[TCS_MAX_DEVICES].line,
				      "too many devices (at most " + std::to_string(TCS_MAX_DEVICES) + ")");
	add_wires(sc, out);
	if (out.devices.size() > TCS_MAX_DEVICES)
		return Error{ sc.file + ": too many devices and wires (at most " + std::to_string(TCS_MAX_DEVICES) + ")" };
	return out;
}

} // namespace tcs
