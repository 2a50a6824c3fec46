// Unit tests for scenario/: every rule a scenario must follow, with the
// exact FILE:LINE of each complaint: syntax, unknown keys and types, [sim],
// models, devices and their signals (also against a world's, with the
// built-in one), controllers. Files, the built-in world itself and units
// are test_scenario_files.cc's and test_scenario_units.cc's.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "default_scenario.h"
#include "scenario.h"
#include "scenario_checks.h"

namespace {

using namespace scenario_checks;
using tcs::DeviceSpec;
using tcs::Scenario;

// ---- syntax, unknown keys, types ---------------------------------------------------

void test_syntax_errors(void **)
{
	expect_error("[sim]\nstep = \n", 2, "");
	expect_error("[sim]\nstep = \"1ms\"\nstep = \"2ms\"\n", 3, "step");
	expect_error("[sim]\nmodel = \"pendulum\"\n\n[sim\n", 4, "");
	expect_error("[sim]\nmodel = \"pendulum\n", 2, "");
}

// Input on which toml++ 3.3 asserts or reaches undefined behaviour must be
// an error like any other; non-ASCII text must come through unchanged.
void test_toml_traps(void **)
{
	expect_error(kHead + "\n[=[model]]\n", 4, "expected bare key starting character");
	expect_error(kHead + "[[=device]]\n", 3, "expected bare key starting character");
	expect_error("[[[sim]]]\n", 1, "expected bare key starting character");
	expect_error("[\n", 1, "expected bare key starting character");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nsignals = [\n\"pendulum.hinge.position\",\n}]\n", 7,
		     "could not determine value type");
	expect_error(kHead + "[model]\nx = [ \xe2\x80\xa8 ]\n", 4, "could not determine value type");
	expect_error("[sim]\nmodel = \"pendulum\"\n[\xc3\xa9]\n", 3, "saw '\xc3\xa9'");
	expect_error(kHead + "[model]\nx = 1\xc2\xa0\n", 4, "expected digit");
	expect_error(kHead + "x = ++[['''\xc2\xa7\n", 3, "could not determine value type");
	expect_error(kHead + "\"caf\xc3\xa9\" = 1\n", 3, "unknown key 'caf\xc3\xa9' in [sim]");
	expect_error(kHead + "[model]\nx = \"\xf3\xb0\x83\xa9\"\n", 4, "(private use) cannot be used");
	expect_error(kHead + "[model]\nx = \"\xed\xa0\x80\"\n", 4, "invalid utf-8");
	Scenario u = parse_ok(kHead + "[[device]]\npath = \"/dev/caf\xc3\xa9/\xe2\x82\xac/\xf0\x9f\xa4\x96\"\n"
				      "kind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\nmode = \"latest\"\n"
				      "[[controller]]\ncommand = \"\"\"ctl \\\n  \xc2\xa7\"\"\"\n");
	assert_string_equal(u.devices[0].path.c_str(), "/dev/caf\xc3\xa9/\xe2\x82\xac/\xf0\x9f\xa4\x96");
	assert_int_equal(u.controllers[0].argv.size(), 2);
	assert_string_equal(u.controllers[0].argv[1].c_str(), "\xc2\xa7");
	// An earlier syntax error is the one reported.
	expect_error("[sim]\nstep = \n[=x]\n", 2, "expected");
	// Valid TOML with look-alikes in strings and comments.
	Scenario s = parse_ok("\xef\xbb\xbf# caf\xc3\xa9 [=x] }\n" + kHead +
			      "[[controller]]\ncommand = '''ctl\n[=x] } \xc3\xa9'''\n"
			      "[[controller]]\ncommand = \"\"\"ctl \\\n [=y] \"a\"\"\"\"\n"
			      "[[controller]]\ncommand = \"ctl '\\\"[=z]'\"\n");
	assert_int_equal(s.controllers.size(), 3);
	assert_string_equal(s.controllers[0].argv[1].c_str(), "[=x]");
	assert_string_equal(s.controllers[0].argv[3].c_str(), "\xc3\xa9");
	assert_int_equal(s.controllers[1].argv.size(), 3);
	assert_string_equal(s.controllers[1].argv[1].c_str(), "[=y]");
	assert_string_equal(s.controllers[1].argv[2].c_str(), "a");
	assert_string_equal(s.controllers[2].argv[1].c_str(), "\"[=z]");
}

void test_unknown_keys(void **)
{
	expect_error("step = \"1ms\"\n" + kHead, 1,
		     "unknown key 'step' at the top level (known: sim, model, device, sensor, can, serial, i2c, controller)");
	expect_error("[sim]\nmodel = \"pendulum\"\nstpe = \"1ms\"\n", 3, "unknown key 'stpe' in [sim] (known: step, model)");
	expect_error(kHead + kSensor + "colour = \"red\"\n", 8,
		     "unknown key 'colour' in [[device]] (known: path, kind, signals, format, mode, rate, limit)");
	expect_error(kHead + "[[controller]]\ncommand = \"x\"\nrate = \"1kHz\"\n", 5,
		     "unknown key 'rate' in [[controller]] (known: command, cpu_scale)");
	// A sub-table is a key of its parent too.
	expect_error("[sim]\nmodel = \"pendulum\"\n[sim.extra]\nx = 1\n", 3, "unknown key 'extra' in [sim]");
	// With several unknown keys the first in the file is named (toml++ sorts them).
	expect_error("[sim]\nmodel = \"pendulum\"\nzz = 1\naa = 2\n", 3, "'zz'");
}

void test_wrong_types(void **)
{
	expect_error("[sim]\nmodel = \"pendulum\"\nstep = 5\n", 3, "step must be a string such as \"1ms\", not an integer");
	expect_error("[sim]\nmodel = \"pendulum\"\nstep = \"fast\"\n", 3, "step: 'fast' is not a duration");
	expect_error("[sim]\nmodel = \"pendulum\"\nstep = \"5\"\n", 3, "'5' needs a unit");
	expect_error("[sim]\nmodel = 3\n", 2, "model must be a string");
	expect_error("sim = 3\n[model]\n", 1, "'sim' must be a table");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n"
			     "rate = \"fast\"\n",
		     7, "rate: 'fast' is not a rate");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n"
			     "rate = \"11e-4000kHz\"\n",
		     7, "rate: '11e-4000kHz' is too slow");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n"
			     "rate = 1000\n",
		     7, "rate must be a string such as \"1kHz\", not an integer");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = \"pendulum.hinge.position\"\n"
			     "rate = \"1kHz\"\n",
		     6, "signals must be an array of strings");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = [\n\"pendulum.hinge.position\",\n"
			     "3]\nrate = \"1kHz\"\n",
		     8, "signals must be strings, not an integer");
	const std::string sig = "signals = [\"pendulum.hinge.position\"]\n";
	expect_error(kHead + "[[device]]\npath = 7\nkind = \"sensor\"\n" + sig, 4, "path must be a string");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"motor\"\n" + sig, 5,
		     "kind must be \"sensor\" or \"actuator\", not \"motor\"");
	expect_error(kHead + kSensor + "format = \"csv\"\n", 8, "format must be \"text\" or \"binary\"");
	expect_error(kHead + kSensor + "mode = \"polled\"\n", 8, "mode must be \"stream\" or \"latest\"");
	expect_error(kHead + "[[device]]\npath = \"/dev/a\"\nkind = \"actuator\"\nsignals = [\"pendulum.hinge.effort\"]\n"
			     "limit = \"5\"\n",
		     7, "limit must be a number, not a string");
	expect_error(kHead + "[model]\nlength = \"long\"\n", 4, "model parameter 'length' must be a number, not a string");
	expect_error(kHead + "[model]\nlength = nan\n", 4, "must be a finite number");
	expect_error(kHead + "[device]\npath = \"/dev/s\"\n", 3, "'device' must be written [[device]]");
	expect_error("controller = \"x\"\n" + kHead, 1, "'controller' must be written [[controller]]");
}

// ---- [sim] -------------------------------------------------------------------------

void test_step(void **)
{
	assert_int_equal(parse_ok(kHead).sim.step_ns, 1000000); // the default
	assert_false(parse_ok(kHead).sim.step_given);             // (a world file's may stand)
	assert_true(parse_ok("[sim]\nstep = \"2ms\"\nmodel = \"pendulum\"\n").sim.step_given);
	assert_int_equal(parse_ok("[sim]\nstep = \"10us\"\nmodel = \"pendulum\"\n").sim.step_ns, 10000);
	Scenario s = parse_ok("# a comment\n[sim]\nstep = \"1s\"\nmodel = \"pendulum\"\n");
	assert_int_equal(s.sim.step_ns, 1000000000);
	assert_int_equal(s.sim.line, 3);
	assert_int_equal(parse_ok("[sim]\nstep = \"2.5 ms\"\nmodel = \"pendulum\"\n").sim.step_ns, 2500000);
	expect_error("[sim]\nmodel = \"pendulum\"\nstep = \"5us\"\n", 3, "step '5us' is out of range (10us to 1s)");
	expect_error("[sim]\nmodel = \"pendulum\"\nstep = \"1.5s\"\n", 3, "out of range");
	expect_error("[sim]\nmodel = \"pendulum\"\nstep = \"9999ns\"\n", 3, "out of range");
}

// ---- models ------------------------------------------------------------------------

void test_single_model_form(void **)
{
	Scenario s = parse_ok(kHead + "[model]\nmass = 2\nlength = 0.5\n");
	assert_int_equal(s.models.size(), 1);
	assert_string_equal(s.models[0].name.c_str(), "pendulum");
	assert_int_equal(s.models[0].line, 2);
	// File order, integers as doubles, each with its line.
	assert_string_equal(s.models[0].params[0].key.c_str(), "mass");
	assert_true(s.models[0].params[0].value == 2.0);
	assert_int_equal(s.models[0].params[0].line, 4);
	assert_string_equal(s.models[0].params[1].key.c_str(), "length");
	assert_int_equal(s.models[0].params[1].line, 5);

	expect_error("[model]\nlength = 1.0\n", 1, "[model] holds the parameters of [sim] model, which is missing");
	expect_error("[sim]\nstep = \"1ms\"\n", 2, "no model");
	expect_error("", 1, "no model");
	expect_error("[sim]\nmodel = \"\"\n", 2, "model is empty");
	expect_error(kHead + "[model]\ntype = \"cartpole\"\n", 4, "'type' does not belong in [model]");
	expect_error(kHead + "[model]\nflag = true\n", 4, "model parameter 'flag' must be a number, not a boolean");
	expect_error("model = \"pendulum\"\n", 1, "'model' must be a [model] table of parameters or [[model]] tables");
	expect_error("[sim]\nmodel = \"my-robot\"\n", 2, "cannot name a model 'my-robot'");
}

void test_model_array_form(void **)
{
	Scenario s = parse_ok("[sim]\nstep = \"2ms\"\n"
			      "[[model]]\nname = \"left\"\ntype = \"pendulum\"\nlength = 2\n"
			      "[[model]]\nname = \"right_2\"\ntype = \"cartpole\"\n"
			      "[[device]]\npath = \"/dev/tcs/x\"\nkind = \"actuator\"\n"
			      "signals = [\"left.hinge.effort\", \"right_2.slider.effort\"]\n");
	assert_int_equal(s.models.size(), 2);
	assert_string_equal(s.models[0].name.c_str(), "left");
	assert_string_equal(s.models[0].type.c_str(), "pendulum");
	assert_int_equal(s.models[0].line, 3);
	assert_int_equal(s.models[0].params.size(), 1);
	assert_string_equal(s.models[0].params[0].key.c_str(), "length");
	assert_int_equal(s.models[0].params[0].line, 6);
	assert_string_equal(s.models[1].name.c_str(), "right_2");
	assert_string_equal(s.models[1].type.c_str(), "cartpole");
	assert_int_equal(s.models[1].line, 7);
	assert_int_equal(s.devices[0].signals[1].line, 13);
	assert_false(s.devices[0].limit.has_value());

	const std::string a = "[[model]]\nname = \"a\"\ntype = \"pendulum\"\n"; // lines 1-3
	expect_error("[sim]\nmodel = \"pendulum\"\n" + a, 2, "[sim] model cannot be combined with [[model]] tables");
	expect_error(a + "[[model]]\nname = \"a\"\ntype = \"pendulum\"\n", 5, "model name 'a' is already used at line 2");
	expect_error(a + "[[model]]\ntype = \"pendulum\"\n", 4, "[[model]] needs a name");
	expect_error(a + "[[model]]\nname = \"b\"\n", 4, "[[model]] needs a type");
	expect_error("[[model]]\nname = \"2nd\"\ntype = \"pendulum\"\n", 2, "model name '2nd' is not an identifier");
	expect_error("[[model]]\nname = \"a.b\"\ntype = \"pendulum\"\n", 2, "is not an identifier");
	expect_error("[[model]]\nname = 1\ntype = \"pendulum\"\n", 2, "name must be a string");
	expect_error(a + "mass = \"heavy\"\n", 4, "model parameter 'mass' must be a number");
	expect_error("model = []\n", 1, "no model");
	// A signal must name a model of this scenario (here: not the type).
	expect_error(a + kSensor, 7, "signal 'pendulum.hinge.position': the scenario has no model 'pendulum' (models: a)");
}

// ---- devices -----------------------------------------------------------------------

void test_device_required_keys(void **)
{
	expect_error(kHead + "\n[[device]]\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n", 4,
		     "[[device]] needs 'path'");
	expect_error(kHead + "\n[[device]]\npath = \"/dev/s\"\nsignals = [\"pendulum.hinge.position\"]\n", 4,
		     "[[device]] needs 'kind'");
	expect_error(kHead + "\n[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\n", 4, "[[device]] needs 'signals'");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = []\n", 6, "signals is empty");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n",
		     3, "a stream sensor needs a rate, such as rate = \"1kHz\"");
}

void test_device_kind_rules(void **)
{
	expect_error(kHead + kSensor + "limit = 5.0\n", 8, "'limit' applies to actuators only");
	const std::string act = "[[device]]\npath = \"/dev/a\"\nkind = \"actuator\"\nsignals = [\"pendulum.hinge.effort\"]\n";
	expect_error(kHead + act + "mode = \"stream\"\n", 7, "'mode' applies to sensors only");
	expect_error(kHead + act + "rate = \"1kHz\"\n", 7, "'rate' applies to sensors only");
	expect_error(kHead + act + "limit = 0\n", 7, "limit must be positive");
	expect_error(kHead + act + "limit = -1.5\n", 7, "limit must be positive");
	expect_error(kHead + act + "limit = inf\n", 7, "limit must be a finite number");
	expect_error(kHead + "[[device]]\npath = \"/dev/a\"\nkind = \"actuator\"\n"
			     "signals = [\"pendulum.hinge.effort\",\n \"pendulum.hinge.velocity\"]\n",
		     7, "actuator signal 'pendulum.hinge.velocity' is not an effort");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n"
			     "mode = \"latest\"\nrate = \"1kHz\"\n",
		     8, "'rate' applies only to mode = \"stream\"");
	// What the kinds do allow, with their defaults.
	Scenario s = parse_ok(kHead + act + "limit = 3\n" + kSensor + "format = \"binary\"\n");
	assert_true(s.devices[0].kind == DeviceSpec::Kind::Actuator);
	assert_true(s.devices[0].limit == 3.0);
	assert_true(s.devices[0].format == DeviceSpec::Format::Text);
	assert_int_equal(s.devices[0].line, 3);
	assert_true(s.devices[1].format == DeviceSpec::Format::Binary);
	assert_true(s.devices[1].mode == DeviceSpec::Mode::Stream);
	assert_int_equal(s.devices[1].line, 8);
	assert_int_equal(s.devices[1].signals[0].line, 11);
}

void test_device_paths(void **)
{
	std::string two = kHead + kSensor + kSensor; // the second at line 8, its path at 9
	expect_error(two, 9, "device path '/dev/s' is already used at line 3");
	for (const char *bad : { "dev/s", "", "/", "/dev//s", "/dev/s/", "/dev/./s", "/dev/../s", "./s" }) {
		std::string text = kHead + "[[device]]\npath = \"" + bad + "\"\nkind = \"sensor\"\n" +
				   "signals = [\"pendulum.hinge.position\"]\n";
		expect_error(text, 4, "must be absolute and normal");
	}
	// Any absolute path may be shadowed, /dev/ttyUSB0 included.
	assert_string_equal(parse_ok(kHead + "[[device]]\npath = \"/dev/ttyUSB0\"\nkind = \"sensor\"\n"
					     "signals = [\"pendulum.hinge.position\"]\nmode = \"latest\"\n")
				    .devices[0]
				    .path.c_str(),
			    "/dev/ttyUSB0");
}

void test_signal_names(void **)
{
	for (const char *bad : { "pendulum.hinge", "pendulum", "pendulum.hinge.angle", "pendulum..position",
				 ".hinge.position", "pendulum.hinge.", "pendulum.hin ge.position", "1x.hinge.position",
				 "pendulum.a..b.pose", "pendulum.hinge.Position" }) {
		std::string text = kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nsignals = [\"" + bad +
				   "\"]\nmode = \"latest\"\n";
		expect_error(text, 6, "is not <model>.<part>.<field> with field one of position, velocity, effort, "
				      "pose, twist");
	}
	auto p = tcs::split_signal_name("arm.link.3.pose");
	assert_true(p.has_value());
	assert_true(p->model == "arm" && p->part == "link.3" && p->field == "pose");
	assert_true(tcs::split_signal_name("pendulum.rod.twist").has_value());
	assert_true(tcs::split_signal_name("pendulum.hinge.effort").has_value());

	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nmode = \"latest\"\n"
			     "signals = [\"pendulum.hinge.position\",\n\"cart.slider.position\"]\n",
		     8, "signal 'cart.slider.position': the scenario has no model 'cart' (models: pendulum)");
	expect_error(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nmode = \"latest\"\n"
			     "signals = [\"pendulum.hinge.position\",\n\"pendulum.hinge.position\"]\n",
		     8, "signal 'pendulum.hinge.position' is listed twice");
	const std::string act = "[[device]]\npath = \"/dev/a\"\nkind = \"actuator\"\nsignals = [\"pendulum.hinge.effort\"]\n";
	std::string twice = kHead + act + "[[device]]\npath = \"/dev/b\"\nkind = \"actuator\"\n"
					  "signals = [\"pendulum.hinge.effort\"]\n";
	expect_error(twice, 10, "signal 'pendulum.hinge.effort' is already driven by /dev/a (line 6)");
	// A sensor may read back an effort that an actuator drives.
	parse_ok(kHead + act + "[[device]]\npath = \"/dev/b\"\nkind = \"sensor\"\nmode = \"latest\"\n"
			       "signals = [\"pendulum.hinge.effort\"]\n");
}

void test_check_signals(void **)
{
	auto r = tcs::default_scenario();
	assert_true(r.ok());
	std::vector<std::string> world = { "pendulum.hinge.position", "pendulum.hinge.velocity",
					   "pendulum.hinge.effort", "pendulum.rod.pose" };
	assert_true(tcs::check_signals(*r, world).ok());
	Scenario s = parse_ok(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nmode = \"latest\"\n"
				      "signals = [\"pendulum.hinge.position\",\n\"pendulum.elbow.position\"]\n");
	auto st = tcs::check_signals(s, world);
	assert_false(st.ok());
	assert_string_equal(st.error().message.c_str(),
			    "t.toml:8: unknown signal 'pendulum.elbow.position' (model 'pendulum' has: "
			    "pendulum.hinge.position, pendulum.hinge.velocity, pendulum.hinge.effort, pendulum.rod.pose)");
	auto none = tcs::check_signals(s, { "other.hinge.position" });
	assert_false(none.ok());
	assert_string_equal(none.error().message.c_str(),
			    "t.toml:7: unknown signal 'pendulum.hinge.position' (model 'pendulum' has no signals)");
	assert_string_equal(tcs::scenario_error(s, 12, "bad").message.c_str(), "t.toml:12: bad");
}

// ---- controllers ---------------------------------------------------------------------

void test_controllers(void **)
{
	Scenario s = parse_ok(kHead + "[[controller]]\ncommand = 'ctl --gain \"1 2\"'\n"
				      "[[controller]]\ncommand = \"ctl2\"\ncpu_scale = 3\n");
	assert_int_equal(s.controllers.size(), 2);
	assert_string_equal(s.controllers[0].command.c_str(), "ctl --gain \"1 2\"");
	assert_int_equal(s.controllers[0].argv.size(), 3);
	assert_string_equal(s.controllers[0].argv[2].c_str(), "1 2");
	assert_int_equal(s.controllers[0].line, 3);
	assert_false(s.controllers[0].cpu_scale.has_value());
	assert_true(s.controllers[1].cpu_scale == 3.0);
	assert_int_equal(s.controllers[1].line, 5);

	expect_error(kHead + "[[controller]]\ncpu_scale = 2\n", 3, "[[controller]] needs a command");
	expect_error(kHead + "[[controller]]\ncommand = \"  \"\n", 4, "command is empty");
	expect_error(kHead + "[[controller]]\ncommand = 'ctl \"x'\n", 4, "command: unterminated double quote");
	expect_error(kHead + "[[controller]]\ncommand = [\"ctl\"]\n", 4, "command must be a string");
	expect_error(kHead + "[[controller]]\ncommand = \"ctl\"\ncpu_scale = 0\n", 5, "cpu_scale must be positive");
	expect_error(kHead + "[[controller]]\ncommand = \"ctl\"\ncpu_scale = \"2\"\n", 5, "cpu_scale must be a number");
}

// ---- robot files (DESIGN §8) -------------------------------------------------------

double param(const Scenario &s, const std::string &key, int *line = nullptr)
{
	for (const auto &p : s.models.at(0).params)
		if (p.key == key) {
			if (line)
				*line = p.line;
			return p.value;
		}
	fail_msg("no parameter '%s'", key.c_str());
	return 0;
}

void test_robot_files(void **)
{
	// A file, its placement as numeric parameters with their lines.
	Scenario s = parse_ok("[[model]]\nname = \"arm\"\nfile = \"robots/rrbot.urdf\"\nfixed = true\n"
			      "pose = [0, 0, 0.1, 0, 0, 1.5]\ninitial_positions = { joint1 = 0.3, \"wrist-1\" = -1 }\n"
			      "initial_velocities = { joint1 = 2 }\n");
	assert_string_equal(s.models[0].type.c_str(), "robots/rrbot.urdf");
	assert_true(param(s, "fixed") == 1.0);
	int line = 0;
	assert_true(param(s, "pose.z", &line) == 0.1 && line == 5);
	assert_true(param(s, "pose.yaw") == 1.5);
	assert_true(param(s, "initial_position.joint1", &line) == 0.3 && line == 6);
	assert_true(param(s, "initial_position.wrist-1") == -1.0);
	assert_true(param(s, "initial_velocity.joint1") == 2.0);
	assert_true(parse_ok("[[model]]\nname = \"a\"\nfile = \"x.sdf\"\nfixed = false\n").models[0].params[0].value == 0);
	// The single-model form takes them in [model].
	s = parse_ok("[sim]\nmodel = \"robots/acrobot.urdf\"\n[model]\nfixed = true\npose = [1, 2, 3, 0, 0, 0]\n");
	assert_string_equal(s.models[0].name.c_str(), "acrobot");
	assert_true(param(s, "pose.x") == 1.0);
	const std::string head = "[[model]]\nname = \"arm\"\n";
	expect_error(head + "file = \"arm.txt\"\n", 3, "file 'arm.txt' is not a robot description: a .urdf, .sdf or .world file");
	expect_error(head + "type = \"pendulum\"\nfile = \"a.urdf\"\n", 4, "has a type (line 3) and a file");
	expect_error(head + "file = 3\n", 3, "file must be a string");
	expect_error(head + "file = \"\"\n", 3, "model file is empty");
	expect_error(head + "file = \"a.urdf\"\nfixed = 1\n", 4, "fixed must be true or false, not an integer");
	expect_error(head + "file = \"a.urdf\"\npose = [0, 0, 0]\n", 4, "pose must be six numbers");
	expect_error(head + "file = \"a.urdf\"\npose = [0, 0, 0, 0, 0, \"x\"]\n", 4, "pose must be a number");
	expect_error(head + "file = \"a.urdf\"\npose = [0, 0, 0, 0, 0, nan]\n", 4, "finite");
	expect_error(head + "file = \"a.urdf\"\ninitial_positions = 3\n", 4, "initial_positions must be a table of joint names");
	expect_error(head + "file = \"a.urdf\"\ninitial_velocities = { j = \"fast\" }\n", 4,
		     "initial_velocities of joint 'j' must be a number");
	expect_error("[[model]]\nfile = \"a.urdf\"\n", 1, "[[model]] needs a name");
	expect_error("[[model]]\nname = \"a\"\n", 1, "needs a type (pendulum, cartpole, double_pendulum, boxes) or a file");
}

// ---- [[sensor]] --------------------------------------------------------------------

void test_sensor_models(void **)
{
	Scenario s = parse_ok(kHead + "[[sensor]]\nsignal = \"pendulum.hinge.position\"\nnoise = 0.0005\nbias = -0.1\n"
				      "resolution = 0.0015\nlatency = \"2ms\"\nrate = \"500Hz\"\n");
	assert_int_equal(s.sensors.size(), 1);
	const tcs::SensorModelSpec &sm = s.sensors[0];
	assert_string_equal(sm.signal.name.c_str(), "pendulum.hinge.position");
	assert_int_equal(sm.line, 3);
	assert_int_equal(sm.signal.line, 4);
	assert_true(sm.noise == 0.0005 && sm.bias == -0.1 && sm.resolution == 0.0015);
	assert_int_equal(sm.latency_ns, 2000000);
	assert_true(sm.rate_hz == 500);
	// Defaults: nothing but the signal.
	s = parse_ok(kHead + "[[sensor]]\nsignal = \"pendulum.rod.pose\"\n");
	assert_true(s.sensors[0].noise == 0 && s.sensors[0].resolution == 0 && s.sensors[0].latency_ns == 0 &&
		    s.sensors[0].rate_hz == 0);
	// A robot file's sensor fields are signal names too.
	parse_ok("[[model]]\nname = \"arm\"\nfile = \"a.sdf\"\n[[sensor]]\nsignal = \"arm.imu.linear_acceleration\"\n");
	const std::string sensor = kHead + "[[sensor]]\nsignal = \"pendulum.hinge.position\"\n";
	expect_error(kHead + "[[sensor]]\nnoise = 1\n", 3, "[[sensor]] needs a signal");
	expect_error(kHead + "[[sensor]]\nsignal = \"pendulum.hinge\"\n", 4, "is not <model>.<part>.<field>");
	expect_error(kHead + "[[sensor]]\nsignal = \"arm.hinge.position\"\n", 4, "the scenario has no model 'arm' (models: pendulum)");
	expect_error(sensor + "noise = -1\n", 5, "noise must be a standard deviation >= 0");
	expect_error(sensor + "noise = inf\n", 5, "noise must be");
	expect_error(sensor + "bias = nan\n", 5, "bias must be a finite number");
	expect_error(sensor + "resolution = 0\n", 5, "resolution must be a quantisation step > 0");
	expect_error(sensor + "latency = \"-2ms\"\n", 5, "latency:");
	expect_error(sensor + "latency = \"11s\"\n", 5, "latency '11s' is more than 10 s");
	expect_error(sensor + "latency = 2\n", 5, "latency must be a string");
	expect_error(sensor + "rate = \"often\"\n", 5, "rate: 'often' is not a rate");
	expect_error(sensor + "colour = 1\n", 5, "unknown key 'colour' in [[sensor]]");
	expect_error(sensor + "[[sensor]]\nsignal = \"pendulum.hinge.position\"\n", 6,
		     "signal 'pendulum.hinge.position' already has a sensor model (line 3)");
	expect_error(kHead + "[sensor]\nsignal = \"pendulum.hinge.position\"\n", 3, "'sensor' must be written [[sensor]]");
	// Checked against the world built: an unknown one is named.
	Scenario ok = parse_ok(kHead + "[[sensor]]\nsignal = \"pendulum.hinge.torque\"\n");
	auto st = tcs::check_signals(ok, { "pendulum.hinge.position" });
	assert_false(st.ok());
	assert_string_equal(st.error().message.c_str(),
			    "t.toml:4: unknown signal 'pendulum.hinge.torque' (model 'pendulum' has: pendulum.hinge.position)");
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_syntax_errors),
		cmocka_unit_test(test_toml_traps),
		cmocka_unit_test(test_unknown_keys),
		cmocka_unit_test(test_wrong_types),
		cmocka_unit_test(test_step),
		cmocka_unit_test(test_single_model_form),
		cmocka_unit_test(test_model_array_form),
		cmocka_unit_test(test_device_required_keys),
		cmocka_unit_test(test_device_kind_rules),
		cmocka_unit_test(test_device_paths),
		cmocka_unit_test(test_signal_names),
		cmocka_unit_test(test_check_signals),
		cmocka_unit_test(test_controllers),
		cmocka_unit_test(test_robot_files),
		cmocka_unit_test(test_sensor_models),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
