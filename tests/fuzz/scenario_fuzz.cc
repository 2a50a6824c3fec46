// The fuzz target for the scenario parser: an input is a scenario file's
// text, parsed by tcs::parse_scenario_text. An error must read
// "NAME:LINE: what" (scenario.h) with LINE a line of the text; a scenario
// accepted must hold what scenario.h says of each field (its wires':
// scenario_wire_promises.cc). The seeds are the files in scenarios/
// (TCS_SCENARIOS_DIR, set by meson) and edge cases.
#include <dirent.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "fuzz_target.h"
#include "read_file.h"
#include "scenario.h"
#include "scenario_units.h"
#include "scenario_wire_promises.h"

#ifndef TCS_SCENARIOS_DIR
#error "TCS_SCENARIOS_DIR must name the source tree's scenarios/ folder"
#endif

namespace {

using tcs_fuzz::check;

// "NAME:LINE: " at the start of message, LINE within the text's lines;
// returns what follows NAME.
std::string check_location(const std::string &message, const std::string &name, const std::string &text)
{
	check(message.compare(0, name.size() + 1, name + ":") == 0);
	size_t i = name.size() + 1, digits = 0;
	long line = 0;
	for (; i < message.size() && message[i] >= '0' && message[i] <= '9' && digits < 10; i++, digits++)
		line = line * 10 + (message[i] - '0');
	check(digits > 0 && message.compare(i, 2, ": ") == 0);
	const long lines = 1 + long(std::count(text.begin(), text.end(), '\n'));
	check(line >= 1 && line <= lines);
	return message.substr(name.size());
}

bool is_normal_absolute(const std::string &p)
{
	if (p.size() < 2 || p[0] != '/' || p.back() == '/' || p.find('\0') != std::string::npos)
		return false;
	auto ends_with = [&p](const std::string &tail) {
		return p.size() >= tail.size() && p.compare(p.size() - tail.size(), tail.size(), tail) == 0;
	};
	return p.find("//") == std::string::npos && p.find("/./") == std::string::npos &&
	       p.find("/../") == std::string::npos && !ends_with("/.") && !ends_with("/..");
}

// What scenario.h says of a scenario it accepted.
void check_scenario(const tcs::Scenario &s, const std::string &name)
{
	using D = tcs::DeviceSpec;
	check(s.file == name);
	check(s.sim.step_ns >= 10000 && s.sim.step_ns <= 1000000000 && s.sim.line >= 0);
	check(!s.models.empty());
	for (size_t i = 0; i < s.models.size(); i++) {
		const tcs::ModelSpec &m = s.models[i];
		check(tcs::is_identifier(m.name) && !m.type.empty() && m.line >= 1);
		for (size_t j = 0; j < i; j++)
			check(s.models[j].name != m.name);
		for (const tcs::ModelParam &p : m.params)
			check(std::isfinite(p.value) && p.line >= 1);
	}
	std::vector<std::string> known;
	for (size_t i = 0; i < s.devices.size(); i++) {
		const D &d = s.devices[i];
		check(is_normal_absolute(d.path) && d.line >= 1 && !d.signals.empty());
		for (size_t j = 0; j < i; j++)
			check(s.devices[j].path != d.path);
		const bool stream = d.kind == D::Kind::Sensor && d.mode == D::Mode::Stream;
		check(d.kind == D::Kind::Sensor || d.mode == D::Mode::Stream);
		if (stream) {
			check(d.rate_hz > 0 && d.rate_hz <= 1e9);
			check(d.period_ns >= 1 && d.period_ns == tcs::rate_period_ns(d.rate_hz));
		} else {
			check(d.rate_hz == 0 && d.period_ns == 0);
		}
		check(!d.limit || (d.kind == D::Kind::Actuator && *d.limit > 0 && std::isfinite(*d.limit)));
		for (const tcs::SignalRef &sig : d.signals) {
			auto parts = tcs::split_signal_name(sig.name);
			check(parts && sig.line >= 1);
			check(d.kind == D::Kind::Sensor || parts->field == "effort");
			check(std::any_of(s.models.begin(), s.models.end(),
					  [&](const tcs::ModelSpec &m) { return m.name == parts->model; }));
			known.push_back(sig.name);
		}
	}
	for (size_t i = 0; i < s.sensors.size(); i++) {
		const tcs::SensorModelSpec &sm = s.sensors[i];
		check(sm.line >= 1 && sm.signal.line >= 1 && tcs::split_signal_name(sm.signal.name));
		check(std::isfinite(sm.noise) && sm.noise >= 0 && std::isfinite(sm.bias));
		check(std::isfinite(sm.resolution) && sm.resolution >= 0);
		check(sm.latency_ns >= 0 && sm.latency_ns <= 10000000000LL && sm.rate_hz >= 0 && sm.rate_hz <= 1e9);
		for (size_t j = 0; j < i; j++)
			check(s.sensors[j].signal.name != sm.signal.name);
		known.push_back(sm.signal.name);
	}
	scenario_wire_promises::check_wires(s, &known);
	for (const tcs::ControllerEntry &c : s.controllers) {
		check(!c.argv.empty() && c.line >= 1);
		check(!c.cpu_scale || (*c.cpu_scale > 0 && *c.cpu_scale <= 1e6));
	}
	// Against the world's signals: all there, then one missing, which a
	// signal (perhaps indexed), a joint or a link needed.
	check(tcs::check_signals(s, known).ok());
	if (!known.empty()) {
		const std::string gone = known.front();
		const std::string stem = gone.substr(0, gone.rfind('.'));
		known.erase(std::remove(known.begin(), known.end(), gone), known.end());
		auto r = tcs::check_signals(s, known);
		check(!r.ok() && r.error().message.rfind(name + ":", 0) == 0);
		const std::string &m = r.error().message;
		check(m.find("unknown signal '" + gone + "'") != std::string::npos ||
		      m.find("unknown signal '" + gone + "[") != std::string::npos ||
		      m.find("unknown joint '" + stem + "'") != std::string::npos ||
		      m.find("unknown link '" + stem + "'") != std::string::npos);
	}
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const std::string text(reinterpret_cast<const char *>(data), size);
	const std::string name = "fuzz.toml";
	auto r = tcs::parse_scenario_text(text, name);
	// The name stands for FILE and nothing else depends on it.
	auto again = tcs::parse_scenario_text(text, "x");
	check(r.ok() == again.ok());
	if (!r.ok()) {
		const std::string what = check_location(r.error().message, name, text);
		check(again.error().message == "x" + what);
		return 0;
	}
	check_scenario(*r, name);
	return 0;
}

const char *tcs_fuzz_name()
{
	return "scenario_fuzz";
}

std::vector<std::string> tcs_fuzz_seeds()
{
	std::vector<std::string> seeds;
	std::vector<std::string> files;
	if (DIR *d = opendir(TCS_SCENARIOS_DIR)) {
		while (struct dirent *e = readdir(d)) {
			std::string n = e->d_name;
			if (n.size() > 5 && n.compare(n.size() - 5, 5, ".toml") == 0)
				files.push_back(n);
		}
		closedir(d);
	}
	std::sort(files.begin(), files.end());
	for (const std::string &f : files)
		if (auto text = tcs::read_file(std::string(TCS_SCENARIOS_DIR) + "/" + f, 1 << 20); text.ok())
			seeds.push_back(*text);
	const std::string head = "[sim]\nmodel = \"pendulum\"\n";
	const std::vector<std::string> more = {
		"",
		"\xef\xbb\xbf# only a comment\n",
		head,
		"sim.step = \"1ms\"\n[[model]]\nname = \"a\"\ntype = \"b.urdf\"\n",
		head + "[model]\nlength = 1e308\nmass = 0x10\n",
		head + "[[device]]\npath = \"/d/s\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\", "
		       "\"pendulum.link.3.pose\"]\nformat = \"binary\"\nrate = \"2.5 kHz\"\n",
		head + "[[device]]\npath = \"/d/l\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.velocity\"]\n"
		       "mode = \"latest\"\n",
		head + "[[device]]\npath = \"/d/a\"\nkind = \"actuator\"\nsignals = [\"pendulum.hinge.effort\"]\n"
		       "limit = 5\n",
		head + "[[device]]\npath = \"/d/s\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n"
		       "rate = \"0.5 Hz\"\n",
		head + "[[controller]]\ncommand = \"\"\"ctl \\\n  'a b' \"c\\\"d\" \xc2\xa7\"\"\"\ncpu_scale = 1e6\n",
		head + "[[controller]]\ncommand = '''ctl\n[=x] } \xc3\xa9'''\n",
		head + "[model]\nx = [ \xe2\x80\xa8 ]\n",
		head + "\"caf\xc3\xa9\" = 1\n",
		"[[model]]\nname = \"arm\"\nfile = \"robots/rrbot.urdf\"\nfixed = true\npose = [0, 0, 0.1, 0, 0, 1.5]\n"
		"initial_positions = { joint1 = 0.3, \"wrist-1\" = -1 }\ninitial_velocities = { joint1 = 0.0 }\n"
		"[[sensor]]\nsignal = \"arm.joint1.position\"\nnoise = 0.0005\nbias = 0.0\nresolution = 0.0015\n"
		"latency = \"2ms\"\nrate = \"500Hz\"\n[[sensor]]\nsignal = \"arm.imu.linear_acceleration\"\n",
		"[sim]\nmodel = \"w.world\"\n[model]\nfixed = false\npose = [1e308, -0, 0, 0, 0, 0]\n",
		"[sim]\nstep = \"10us\"\nstep = \"1s\"\n",
		// The wires (DESIGN §9).
		head + "[[can]]\ninterface = \"can0\"\nbitrate = \"1Mbit/s\"\ndata_bitrate = \"5Mbit/s\"\n"
		       "[[can.motor]]\nprotocol = \"mit\"\nid = 1\nreply_id = 0\njoint = \"pendulum.hinge\"\n"
		       "position_range = 12.5\nvelocity_range = 50\ntorque_range = 5\nkp_max = 500\nkd_max = 5\n"
		       "[[can.frame]]\nid = 0x100\nrate = \"100Hz\"\nbyte_order = \"little\"\nfields = [\n"
		       "{ signal = \"pendulum.hinge.position\", type = \"int16\", scale = 0.001, offset = 0.0, start = 0 },\n"
		       "{ signal = \"pendulum.rod.pose[2]\", type = \"float32\", start = 60 }]\n"
		       "[[can.frame]]\nid = 0x1FFFFFFF\nextended = true\ncommand = true\nbyte_order = \"big\"\n"
		       "fields = [{ signal = \"pendulum.u.effort[1]\", type = \"int32\" }]\n",
		head + "[[can]]\ninterface = \"vcan_1.x-y\"\nbitrate = 125000\n[[can.frame]]\nid = 0\nrate = \"1kHz\"\n"
		       "command = false\nbyte_order = \"big\"\nfields = []\n[[can.frame]]\nid = 0x7FF\ncommand = true\n"
		       "byte_order = \"little\"\n[[can.frame.fields]]\nsignal = \"pendulum.hinge.effort\"\ntype = \"uint8\"\n"
		       "start = 7\n[[can]]\ninterface = \"can1\"\nbitrate = \"83.333kbit/s\"\n",
		head + "[[device]]\npath = \"/dev/ttyUSB1\"\nkind = \"actuator\"\nsignals = [\"pendulum.a.effort\"]\n"
		       "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 57600\n[[serial.servo]]\nprotocol = \"dynamixel2\"\n"
		       "id = 1\njoint = \"pendulum.hinge\"\n[[serial.servo]]\nprotocol = \"dynamixel2\"\nid = 252\n"
		       "joint = \"pendulum.b\"\n[[serial]]\npath = \"/dev/ttyS0\"\nbaud = 50\n",
		head + "[[i2c]]\nbus = 1\nclock = \"400kHz\"\n[[i2c.device]]\naddress = 0x68\nchip = \"mpu6050\"\n"
		       "link = \"pendulum.rod\"\naccel_noise = 0.05\ngyro_noise = 0.001\n[[i2c.device]]\naddress = 0x69\n"
		       "chip = \"mpu6050\"\nlink = \"pendulum.rod\"\n[[i2c]]\nbus = 255\nclock = 3400000\n",
		"[\n",
		"[[[sim]]]\n",
	};
	seeds.insert(seeds.end(), more.begin(), more.end());
	return seeds;
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { "[sim]\n", "[model]\n", "[[model]]\n", "[[device]]\n", "[[controller]]\n", "[sim.x]\n",
		 "step = ", "model = ", "name = ", "type = ", "path = ", "kind = ", "signals = ", "format = ",
		 "mode = ", "rate = ", "limit = ", "command = ", "cpu_scale = ", "[[sensor]]\n", "signal = ",
		 "noise = ", "bias = ", "resolution = ", "latency = ", "file = ", "fixed = ", "pose = ",
		 "initial_positions = ", "initial_velocities = ", "[0, 0, 0, 0, 0, 0]", "\"a.urdf\"", "\"w.world\"",
		 "\"arm.imu.linear_acceleration\"", "\"pendulum.rod.orientation\"", "\"sensor\"", "\"actuator\"",
		 "\"text\"", "\"binary\"", "\"stream\"", "\"latest\"", "\"pendulum\"", "\"cartpole\"",
		 "\"double_pendulum\"", "\"boxes\"", "\"x.sdf\"", "\"../r.urdf\"", "\"/dev/tcs/a\"",
		 "\"pendulum.hinge.effort\"", "\"pendulum.hinge.position\"", "[\"pendulum.hinge.velocity\"]",
		 " Hz\"", "kHz\"", "MHz\"", "ns\"", "us\"", "\xc2\xb5s\"", "ms\"", "s\"", "1e-12", "1e308", "1e-4000",
		 "inf", "nan", "-0", "0x7fffffffffffffff", "9223372036854775808", "1979-05-27T07:32:00Z", "true",
		 "'''", "\"\"\"", "\\u00e9", "\\U0001F916", "\xc2\xa0", "\xe2\x80\xa8", "\xef\xbb\xbf",
		 "\xf3\xb0\x83\xa9", "# c\n", " = ", "{ a = 1 }", "[1, 2]", ".", "\n", "[[can]]\n", "[[can.motor]]\n",
		 "[[can.frame]]\n", "[[can.frame.fields]]\n", "[[serial]]\n", "[[serial.servo]]\n", "[[i2c]]\n",
		 "[[i2c.device]]\n", "interface = ", "bitrate = ", "data_bitrate = ", "protocol = ", "id = ",
		 "reply_id = ", "joint = ", "extended = ", "command = ", "byte_order = ", "fields = ", "start = ",
		 "scale = ", "offset = ", "baud = ", "bus = ", "clock = ", "address = ", "chip = ", "link = ",
		 "\"mit\"", "\"dynamixel2\"", "\"mpu6050\"", "\"can0\"", "\"int16\"", "\"float32\"", "\"uint8\"",
		 "\"little\"", "\"big\"", "\"pendulum.hinge\"", "\"pendulum.rod\"", "\"pendulum.rod.pose[6]\"",
		 "Mbit/s\"", "kbit/s\"", "0x7FF", "0x1FFFFFFF", "0x68", "0x77", "252", "57600", "[{ signal = ",
		 ", type = \"int32\" }]" };
}

// Whole lines moved about: a key into another table, a table twice.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	std::vector<std::string> lines;
	size_t start = 0;
	for (size_t nl; (nl = s.find('\n', start)) != std::string::npos; start = nl + 1)
		lines.push_back(s.substr(start, nl + 1 - start));
	if (start < s.size())
		lines.push_back(s.substr(start));
	if (lines.size() < 2)
		return false;
	const size_t a = rng.below(lines.size()), b = rng.below(lines.size());
	switch (rng.below(3)) {
	case 0:
		std::swap(lines[a], lines[b]);
		break;
	case 1: {
		const std::string copy = lines[a];
		lines.insert(lines.begin() + long(b), copy);
		break;
	}
	case 2:
		lines.erase(lines.begin() + long(a));
		break;
	}
	s.clear();
	for (const std::string &l : lines)
		s += l + (l.empty() || l.back() != '\n' ? "\n" : "");
	return true;
}
