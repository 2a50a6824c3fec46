// The robot loader on malformed and hostile files (tests/robots/bad, and
// files written here): each gives one line "FILE:LINE: cause", never a
// crash nor a hang.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

#include <chrono>
#include <string>

extern "C" {
#include <cmocka.h>
}

#include "robot_load_checks.h"
#include "test_files.h"

int run_bad_robot_tests();

namespace {

using namespace robot_checks;

std::string bad(const char *name)
{
	return std::string(TCS_TEST_ROBOTS_DIR) + "/bad/" + name;
}

void test_missing_and_not_xml(void **)
{
	load_fails(bad("nothere.urdf"), 0, { "No such file or directory" });
	load_fails(bad("truncated.urdf"), 4, { "XML syntax error" });
	load_fails(bad("truncated.sdf"), 6, { "XML syntax error" });
	load_fails(bad("empty.urdf"), 0, { "XML syntax error", "empty" });
	load_fails(bad("not_a_robot.xml"), 2, { "neither URDF", "<launch>" });
	// urdfdom's words (libsdformat alone says "Unable to read file"); it
	// names no link, so no line.
	load_fails(bad("bad_attribute.urdf"), 0, { "[zero]", "double" });
}

void test_bad_masses(void **)
{
	load_fails(bad("nan_mass.urdf"), 5, { "nan", "not a finite number" });
	load_fails(bad("nan_mass.sdf"), 6, { "nan", "not a finite number" });
	load_fails(bad("negative_mass.sdf"), 6, { "-2", "negative mass" });
	load_fails(bad("zero_inertia.urdf"), 9, { "'arm'", "inertia", "not positive definite" });
	load_fails(bad("zero_inertia.sdf"), 4, { "'a'", "inertia", "not positive definite" });
	load_fails(bad("massless_moving.urdf"), 4, { "'ghost_arm'", "no mass", "moves" });
}

void test_bad_trees(void **)
{
	load_fails(bad("loop.urdf"), 8, { "'c'", "child of two joints", "loop" });
	load_fails(bad("loop.sdf"), 9, { "'c'", "child of two joints", "loop" });
	load_fails(bad("cycle.urdf"), 7, { "loop", "'cb'" });
	load_fails(bad("unknown_link.urdf"), 4, { "'ghost'", "does not declare" });
	// libsdformat's own words; the line is that of the joint it names.
	load_fails(bad("unknown_link.sdf"), 5, { "ghost", "not found" });
	load_fails(bad("duplicate.urdf"), 4, { "'a'", "declared twice", "line 3" });
	load_fails(bad("duplicate.sdf"), 5, { "[a]", "already exists" });
}

void test_unsupported(void **)
{
	for (const char *t : { "screw", "revolute2", "gearbox" })
		load_fails(bad((std::string(t) + ".sdf").c_str()), 6, { "tcs cannot simulate joint type", t });
	load_fails(bad("floating.urdf"), 5, { "tcs cannot simulate joint type floating" });
	// Meshes are read (test_mesh_load.cc); these are not found.
	load_fails(bad("mesh.urdf"), 7, { "mesh 'package://robot/meshes/a.stl' not found" });
	load_fails(bad("mesh.sdf"), 6, { "mesh 'meshes/a.stl' not found" });
}

// A chain of n links, as URDF or SDF.
std::string chain(int n, bool urdf)
{
	std::string s = "<?xml version=\"1.0\"?>\n";
	s += urdf ? "<robot name=\"chain\">\n" : "<sdf version=\"1.9\"><model name=\"chain\">\n";
	const char *in = urdf ? "<inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>"
			      : "<inertial><mass>1</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz></inertia></inertial>";
	for (int i = 0; i < n; i++)
		s += "<link name=\"l" + std::to_string(i) + "\">" + in + "</link>\n";
	for (int i = 1; i < n; i++) {
		std::string p = "l" + std::to_string(i - 1), c = "l" + std::to_string(i);
		s += "<joint name=\"j" + std::to_string(i) + "\" type=\"revolute\">";
		s += urdf ? "<parent link=\"" + p + "\"/><child link=\"" + c +
				    "\"/><axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>"
			  : "<parent>" + p + "</parent><child>" + c + "</child><axis><xyz>0 1 0</xyz></axis>";
		s += "</joint>\n";
	}
	s += urdf ? "</robot>\n" : "</model></sdf>\n";
	return s;
}

void test_ten_thousand_links(void **)
{
	for (bool urdf : { true, false }) {
		std::string path = test_files::test_path(urdf ? "chain.urdf" : "chain.sdf");
		test_files::spit(path, chain(10000, urdf));
		auto t0 = std::chrono::steady_clock::now();
		// The 1001st link, on line 1003, is one too many.
		load_fails(path, 1003, { "more than 1000 links" });
		double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		print_message("10,000 links (%s) refused in %.3f s\n", urdf ? "URDF" : "SDF", s);
	}
	// A long chain within the limit loads.
	for (bool urdf : { true, false }) {
		std::string path = test_files::test_path(urdf ? "chain100.urdf" : "chain100.sdf");
		test_files::spit(path, chain(100, urdf));
		Description d = load_ok(path);
		assert_int_equal(d.models.at(0).links.size(), 100);
		assert_int_equal(d.models.at(0).joints.size(), 99);
	}
}

// Every prefix of a good file, cut at each of many points: an error, never
// a crash.
void test_truncations(void **)
{
	std::string text = test_files::slurp(std::string(TCS_TEST_ROBOTS_DIR) + "/two_link_arm.sdf");
	std::string path = test_files::test_path("cut.sdf");
	// (Short of "</sdf>\n": the whole file but its last newline loads.)
	for (size_t n = 0; n + 8 < text.size(); n += 97) {
		test_files::spit(path, text.substr(0, n));
		auto r = load_robot_file(path);
		if (r.ok())
			print_error("the first %zu bytes load\n", n);
		assert_false(r.ok());
		assert_true(r.error().message.rfind(path + ":", 0) == 0);
	}
}

int setup(void **)
{
	return test_files::test_dir_open("tcs-robot-load") ? 0 : -1;
}

int teardown(void **)
{
	test_files::test_dir_close();
	return 0;
}

} // namespace

int run_bad_robot_tests()
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_missing_and_not_xml),
		cmocka_unit_test(test_bad_masses),
		cmocka_unit_test(test_bad_trees),
		cmocka_unit_test(test_unsupported),
		cmocka_unit_test(test_ten_thousand_links),
		cmocka_unit_test(test_truncations),
	};
	return cmocka_run_group_tests_name("malformed and hostile robot files", tests, setup, teardown);
}
