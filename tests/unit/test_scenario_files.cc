// Unit tests for scenario/: scenarios read from files: the built-in world
// and scenarios/pendulum.toml, which documents it; every file in
// scenarios/; model paths resolved against a file's folder; files that
// cannot be read.
#include <dirent.h>
#include <unistd.h>

#include <algorithm>
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

#ifndef TCS_SCENARIOS_DIR
#error "TCS_SCENARIOS_DIR must name the source tree's scenarios/ folder"
#endif

namespace {

using namespace scenario_checks;
using tcs::DeviceSpec;
using tcs::Scenario;

// ---- the built-in default -------------------------------------------------------

void test_default_scenario(void **)
{
	auto r = tcs::default_scenario();
	if (!r.ok()) {
		print_error("%s\n", r.error().message.c_str());
		fail();
	}
	const Scenario &s = *r;
	assert_int_equal(s.sim.step_ns, 1000000);
	assert_int_equal(s.models.size(), 1);
	assert_string_equal(s.models[0].name.c_str(), "pendulum");
	assert_string_equal(s.models[0].type.c_str(), "pendulum");
	const auto &p = s.models[0].params;
	assert_int_equal(p.size(), 3);
	assert_string_equal(p[0].key.c_str(), "length");
	assert_true(p[0].value == 1.0);
	assert_string_equal(p[1].key.c_str(), "mass");
	assert_true(p[1].value == 1.0);
	assert_string_equal(p[2].key.c_str(), "initial_angle");
	assert_true(p[2].value == 0.0);

	assert_int_equal(s.devices.size(), 2);
	const DeviceSpec &st = s.devices[0];
	assert_string_equal(st.path.c_str(), "/dev/tcs/pendulum/state");
	assert_true(st.kind == DeviceSpec::Kind::Sensor);
	assert_int_equal(st.signals.size(), 2);
	assert_string_equal(st.signals[0].name.c_str(), "pendulum.hinge.position");
	assert_string_equal(st.signals[1].name.c_str(), "pendulum.hinge.velocity");
	assert_true(st.format == DeviceSpec::Format::Text);
	assert_true(st.mode == DeviceSpec::Mode::Stream);
	assert_true(st.rate_hz == 1000.0);
	assert_int_equal(st.period_ns, 1000000);
	assert_false(st.limit.has_value());

	const DeviceSpec &tq = s.devices[1];
	assert_string_equal(tq.path.c_str(), "/dev/tcs/pendulum/torque");
	assert_true(tq.kind == DeviceSpec::Kind::Actuator);
	assert_int_equal(tq.signals.size(), 1);
	assert_string_equal(tq.signals[0].name.c_str(), "pendulum.hinge.effort");
	assert_true(tq.format == DeviceSpec::Format::Text);
	assert_true(tq.limit.has_value() && *tq.limit == 5.0);
	assert_int_equal(tq.period_ns, 0);
	assert_true(s.controllers.empty());
	// Lines refer to the built-in text, and the file name says it is built in.
	assert_true(s.file.find("built-in") != std::string::npos);
	assert_int_equal(s.devices[0].line, 10);
}

// scenarios/pendulum.toml documents the default: they must not drift apart.
void test_pendulum_file_is_the_default(void **)
{
	auto f = tcs::parse_scenario_file(TCS_SCENARIOS_DIR "/pendulum.toml");
	auto d = tcs::default_scenario();
	assert_true(f.ok() && d.ok());
	assert_int_equal(f->sim.step_ns, d->sim.step_ns);
	assert_int_equal(f->models.size(), 1);
	assert_string_equal(f->models[0].type.c_str(), d->models[0].type.c_str());
	assert_int_equal(f->models[0].params.size(), d->models[0].params.size());
	for (size_t i = 0; i < f->models[0].params.size(); i++) {
		assert_string_equal(f->models[0].params[i].key.c_str(), d->models[0].params[i].key.c_str());
		assert_true(f->models[0].params[i].value == d->models[0].params[i].value);
	}
	assert_int_equal(f->devices.size(), d->devices.size());
	for (size_t i = 0; i < f->devices.size(); i++) {
		const DeviceSpec &a = f->devices[i], &b = d->devices[i];
		assert_string_equal(a.path.c_str(), b.path.c_str());
		assert_true(a.kind == b.kind && a.format == b.format && a.mode == b.mode);
		assert_int_equal(a.period_ns, b.period_ns);
		assert_true(a.limit == b.limit);
		assert_int_equal(a.signals.size(), b.signals.size());
		for (size_t j = 0; j < a.signals.size(); j++)
			assert_string_equal(a.signals[j].name.c_str(), b.signals[j].name.c_str());
	}
}

// ---- the files in scenarios/ -----------------------------------------------------

void test_every_scenario_file_parses(void **)
{
	DIR *dir = opendir(TCS_SCENARIOS_DIR);
	assert_non_null(dir);
	std::vector<std::string> names;
	while (struct dirent *e = readdir(dir)) {
		std::string n = e->d_name;
		if (n.size() > 5 && n.substr(n.size() - 5) == ".toml")
			names.push_back(n);
	}
	closedir(dir);
	std::sort(names.begin(), names.end());
	for (const char *want : { "boxes.toml", "cartpole.toml", "double_pendulum.toml", "pendulum.toml",
				  "two_pendulums.toml" })
		assert_true(std::find(names.begin(), names.end(), want) != names.end());
	for (const std::string &n : names) {
		auto r = tcs::parse_scenario_file(TCS_SCENARIOS_DIR "/" + n);
		if (!r.ok()) {
			print_error("%s\n", r.error().message.c_str());
			fail();
		}
		assert_false(r->models.empty());
		assert_false(r->devices.empty());
	}
}

void test_two_pendulums_file(void **)
{
	auto r = tcs::parse_scenario_file(TCS_SCENARIOS_DIR "/two_pendulums.toml");
	assert_true(r.ok());
	assert_int_equal(r->models.size(), 2);
	assert_string_equal(r->models[0].name.c_str(), "left");
	assert_string_equal(r->models[1].name.c_str(), "right");
	assert_string_equal(r->models[1].type.c_str(), "pendulum");
	assert_int_equal(r->devices.size(), 4);
	assert_int_equal(r->devices[0].period_ns, 1000000);
	assert_int_equal(r->devices[2].period_ns, 4000000);
	assert_int_equal(r->controllers.size(), 2);
	// The example controller at two rates (however it is found, whatever else it is told).
	const auto &a = r->controllers[0].argv, &b = r->controllers[1].argv;
	auto is_pd = [](const std::string &p) { return p.size() >= 11 && p.substr(p.size() - 11) == "pendulum_pd"; };
	assert_true(a.size() >= 3 && is_pd(a[0]) && a[1] == "--rate" && a[2] == "1000");
	assert_true(b.size() >= 3 && is_pd(b[0]) && b[1] == "--rate" && b[2] == "250");
	assert_false(r->controllers[0].cpu_scale.has_value());
	assert_true(r->controllers[1].cpu_scale == 2.0);
}

// ---- files elsewhere ------------------------------------------------------------------

void test_model_paths(void **)
{
	char dir[] = "/tmp/tcs_scenario_XXXXXX";
	assert_non_null(mkdtemp(dir));
	std::string file = std::string(dir) + "/arm.toml";
	FILE *f = fopen(file.c_str(), "w");
	assert_non_null(f);
	fputs("[sim]\nmodel = \"robots/arm.urdf\"\n[[device]]\npath = \"/dev/arm\"\nkind = \"sensor\"\n"
	      "signals = [\"arm.wrist-1.position\"]\nmode = \"latest\"\n",
	      f);
	fclose(f);
	auto r = tcs::parse_scenario_file(file);
	unlink(file.c_str());
	rmdir(dir);
	if (!r.ok()) {
		print_error("%s\n", r.error().message.c_str());
		fail();
	}
	// Named after the file's stem; the path resolved against the scenario's folder.
	assert_string_equal(r->models[0].name.c_str(), "arm");
	assert_string_equal(r->models[0].type.c_str(), (std::string(dir) + "/robots/arm.urdf").c_str());
	assert_true(r->devices[0].mode == DeviceSpec::Mode::Latest);
	assert_int_equal(r->devices[0].period_ns, 0);
	// Absolute paths, and text with no folder, keep the path as written.
	assert_string_equal(parse_ok("[sim]\nmodel = \"/r/b.sdf\"\n").models[0].type.c_str(), "/r/b.sdf");
	assert_string_equal(parse_ok("[sim]\nmodel = \"b.sdf\"\n").models[0].type.c_str(), "b.sdf");
}

void test_file_errors(void **)
{
	auto r = tcs::parse_scenario_file("/nonexistent/w.toml");
	assert_false(r.ok());
	assert_string_equal(r.error().message.c_str(), "/nonexistent/w.toml: No such file or directory");
	auto d = tcs::parse_scenario_file("/");
	assert_false(d.ok());
	assert_true(d.error().message.rfind("/: ", 0) == 0);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_default_scenario),
		cmocka_unit_test(test_pendulum_file_is_the_default),
		cmocka_unit_test(test_every_scenario_file_parses),
		cmocka_unit_test(test_two_pendulums_file),
		cmocka_unit_test(test_model_paths),
		cmocka_unit_test(test_file_errors),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
