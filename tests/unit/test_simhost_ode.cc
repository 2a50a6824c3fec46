// Unit tests for the built-in ODE simulation plug-in, through its C ABI
// only: the ABI and its model types, the signal table, error messages,
// independence of models in one world, and the determinism of the boxes
// workload. The physics of each model is test_simhost_physics.cc's.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "simhost_checks.h"
#include "tcs/simhost.h"

namespace {

using namespace simhost_checks;

void test_abi(void **)
{
	const struct tcs_simhost_plugin *p = ode();
	assert_non_null(p);
	assert_int_equal(p->abi_version, TCS_SIMHOST_ABI_VERSION);
	assert_string_equal(p->name, "ode");
	std::vector<std::string> types;
	for (const char *const *t = p->model_types; *t; t++)
		types.emplace_back(*t);
	assert_int_equal(types.size(), 4);
	// Every listed type exists with its defaults (boxes made small to be quick).
	for (const std::string &t : types) {
		Spec s("m", t.c_str());
		if (t == "boxes")
			s = Spec("m", "boxes", { { "count", 10 } });
		Sim sim({ s });
		assert_true(ode()->signal_count(sim.get()) > 0);
		sim.step(10);
	}
	// An empty world is a world.
	Sim none({});
	assert_int_equal(ode()->signal_count(none.get()), 0);
	none.step();
}

void test_pendulum_signals(void **)
{
	Sim sim({ Spec("pendulum", "pendulum") });
	struct {
		const char *name;
		uint32_t width;
		bool writable;
		const char *unit;
	} want[] = {
		{ "pendulum.hinge.position", 1, false, "rad" },
		{ "pendulum.hinge.velocity", 1, false, "rad/s" },
		{ "pendulum.hinge.effort", 1, true, "N*m" },
		{ "pendulum.rod.pose", 7, false, nullptr },
		{ "pendulum.rod.twist", 6, false, nullptr },
	};
	assert_int_equal(ode()->signal_count(sim.get()), 5);
	for (size_t i = 0; i < 5; i++) {
		const struct tcs_sim_signal_info *si = ode()->signal_info(sim.get(), i);
		assert_non_null(si);
		assert_string_equal(si->name, want[i].name);
		assert_int_equal(si->width, want[i].width);
		assert_int_equal((si->flags & TCS_SIM_SIGNAL_WRITABLE) != 0, want[i].writable);
		assert_non_null(si->unit);
		if (want[i].unit)
			assert_string_equal(si->unit, want[i].unit);
	}
	assert_null(ode()->signal_info(sim.get(), 5));

	// Bad indices and read-only signals are refused; so is a value that
	// would poison the state.
	double v[7] = { 1 };
	assert_int_equal(ode()->read(sim.get(), 5, v), -1);
	assert_int_equal(ode()->write(sim.get(), 5, v), -1);
	assert_int_equal(ode()->write(sim.get(), 0, v), -1);
	assert_int_equal(ode()->write(sim.get(), 4, v), -1);
	assert_int_equal(sim.set("pendulum.hinge.effort", NAN), -1);
	assert_int_equal(sim.set("pendulum.hinge.effort", INFINITY), -1);
	assert_int_equal(sim.set("pendulum.hinge.effort", 0.5), 0);

	// At rest, hanging: the centre of mass L/2 below the hinge, upright
	// orientation quaternion, no motion.
	std::vector<double> pose = sim.values("pendulum.rod.pose");
	assert_float_equal(pose[0], 0, 1e-12);
	assert_float_equal(pose[2], -0.5, 1e-12);
	assert_float_equal(pose[3], 1, 1e-12);
	for (double t : sim.values("pendulum.rod.twist"))
		assert_float_equal(t, 0, 1e-12);
}

void test_errors(void **)
{
	std::string e = create_error({ Spec("p", "pendulm") });
	expect_contains(e, "'pendulm'");
	expect_contains(e, "pendulum, cartpole, double_pendulum, boxes");

	e = create_error({ Spec("p", "pendulum", { { "lenght", 1 } }) });
	expect_contains(e, "pendulum");
	expect_contains(e, "'lenght'");
	expect_contains(e, "length, mass, damping, initial_angle, initial_velocity");

	e = create_error({ Spec("p", "pendulum", { { "length", -1 } }) });
	expect_contains(e, "'length'");
	expect_contains(e, "> 0");
	expect_contains(create_error({ Spec("p", "pendulum", { { "mass", 0 } }) }), "'mass'");
	expect_contains(create_error({ Spec("p", "pendulum", { { "damping", -0.1 } }) }), "'damping'");
	expect_contains(create_error({ Spec("p", "pendulum", { { "initial_angle", NAN } }) }), "'initial_angle'");
	expect_contains(create_error({ Spec("p", "pendulum", { { "mass", 1 }, { "mass", 2 } }) }), "twice");
	expect_contains(create_error({ Spec("b", "boxes", { { "count", 0 } }) }), "'count'");
	expect_contains(create_error({ Spec("b", "boxes", { { "count", 1.5 } }) }), "'count'");
	expect_contains(create_error({ Spec("b", "boxes", { { "seed", -1 } }) }), "'seed'");
	expect_contains(create_error({ Spec("b", "boxes", { { "arena_size", 0.5 } }) }), "do not fit");
	expect_contains(create_error({ Spec("c", "cartpole", { { "track_limit", 0 } }) }), "'track_limit'");
	expect_contains(create_error({ Spec("d", "double_pendulum", { { "length3", 1 } }) }), "'length3'");

	// The model's name is in the message too: several may share a type.
	expect_contains(create_error({ Spec("left", "pendulum"), Spec("right", "pendulum", { { "mass", -2 } }) }),
			"'right'");
	expect_contains(create_error({ Spec("p", "pendulum"), Spec("p", "cartpole") }), "same name");
	expect_contains(create_error({ Spec("a.b", "pendulum") }), "name");
	expect_contains(create_error({ Spec("", "pendulum") }), "name");
	expect_contains(create_error({ Spec("p", "pendulum") }, 0), "step");

	// A short buffer gets a truncated, terminated message.
	Spec bad("p", "pendulum", { { "lenght", 1 } });
	struct tcs_sim_model m = bad.model();
	char small[8];
	memset(small, 'x', sizeof small);
	assert_null(ode()->create(&m, 1, kMs, small, sizeof small));
	assert_int_equal(strlen(small), sizeof small - 1);
	assert_null(ode()->create(&m, 1, kMs, nullptr, 0));
}

void test_two_pendulums(void **)
{
	Sim both({ Spec("left", "pendulum", { { "initial_angle", 0.5 } }), Spec("right", "pendulum") });
	Sim alone({ Spec("left", "pendulum", { { "initial_angle", 0.5 } }) });
	assert_int_equal(ode()->signal_count(both.get()), 10);
	// They hang from the same point, and pass through each other.
	both.set("right.hinge.effort", -1.0);
	for (int i = 0; i < 2000; i++) {
		both.step();
		alone.step();
		assert_float_equal(both.get("left.hinge.position"), alone.get("left.hinge.position"), 0);
	}
	assert_true(both.get("right.hinge.position") < -0.05);
	assert_float_equal(both.get("right.hinge.effort"), -1.0, 0);
	assert_float_equal(both.get("left.hinge.effort"), 0, 0);
}

void test_boxes(void **)
{
	Sim sim({ Spec("boxes", "boxes") });
	assert_int_equal(ode()->signal_count(sim.get()), 2001);
	assert_int_equal(ode()->signal_info(sim.get(), sim.index("boxes.box0.pose"))->width, 7);
	assert_int_equal(ode()->signal_info(sim.get(), sim.index("boxes.box999.twist"))->width, 6);
	for (size_t i = 0; i < ode()->signal_count(sim.get()); i++)
		assert_int_equal(ode()->signal_info(sim.get(), i)->flags & TCS_SIM_SIGNAL_WRITABLE, 0);
	assert_int_equal(sim.set("boxes.box0.pose", 0), -1);

	sim.step(200);
	assert_true(sim.get("boxes.arena.contacts") >= 1000);
	// The arena is 10 m square by default (0.1 m boxes covering a tenth).
	double moving = 0;
	for (int i = 0; i < 1000; i++) {
		std::string box = "boxes.box" + std::to_string(i);
		std::vector<double> p = sim.values((box + ".pose").c_str());
		assert_true(std::fabs(p[0]) <= 5.0 - 0.05 + 1e-3);
		assert_true(std::fabs(p[1]) <= 5.0 - 0.05 + 1e-3);
		assert_true(p[2] > 0 && p[2] < 0.5);
		std::vector<double> t = sim.values((box + ".twist").c_str());
		moving += std::hypot(t[0], t[1]) > 0.1;
	}
	assert_true(moving > 500); // still sliding, not settled
}

// The whole state of a boxes world, bit for bit.
std::vector<double> box_state(const Sim &sim)
{
	std::vector<double> all;
	for (size_t i = 0; i < ode()->signal_count(sim.get()); i++) {
		double v[7];
		assert_int_equal(ode()->read(sim.get(), i, v), 0);
		all.insert(all.end(), v, v + ode()->signal_info(sim.get(), i)->width);
	}
	return all;
}

void test_boxes_deterministic(void **)
{
	Spec spec("b", "boxes", { { "count", 300 }, { "seed", 7 } });
	Sim a({ spec }), b({ spec });
	Sim other({ Spec("b", "boxes", { { "count", 300 }, { "seed", 8 } }) });
	assert_true(box_state(a) == box_state(b));
	assert_true(box_state(a) != box_state(other));
	// Interleaved unevenly: each world's solver sees only its own random
	// sequence.
	a.step(50);
	other.step(20);
	b.step(20);
	other.step(20);
	b.step(30);
	a.step(150);
	b.step(150);
	assert_true(box_state(a) == box_state(b));
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_abi),
		cmocka_unit_test(test_pendulum_signals),
		cmocka_unit_test(test_errors),
		cmocka_unit_test(test_two_pendulums),
		cmocka_unit_test(test_boxes),
		cmocka_unit_test(test_boxes_deterministic),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
