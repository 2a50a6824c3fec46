// What the ODE plug-in's tests share: the plug-in, through its C ABI only
// (as the coordinator and any other host see it), a model's description,
// a world destroyed at scope end with its signals looked up by name, and
// create()'s refusals. Include after <cmocka.h>.
#pragma once

#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

#include "tcs/simhost.h"

namespace simhost_checks {

inline constexpr double g = 9.81;
inline constexpr int64_t kMs = 1000000;

inline const struct tcs_simhost_plugin *ode()
{
	return tcs_simhost_ode_plugin();
}

struct Param {
	const char *key;
	double value;
};

// One model's description, kept alive for create().
struct Spec {
	const char *name;
	const char *type;
	std::vector<const char *> keys;
	std::vector<double> values;

	Spec(const char *n, const char *t, std::initializer_list<Param> ps = {}) : name(n), type(t)
	{
		for (const Param &p : ps) {
			keys.push_back(p.key);
			values.push_back(p.value);
		}
	}
	struct tcs_sim_model model() const
	{
		return { name, type, keys.data(), values.data(), keys.size() };
	}
};

// A world, destroyed at scope end; lookups by name fail the test when the
// signal does not exist.
class Sim {
public:
	explicit Sim(std::initializer_list<Spec> specs, int64_t step_ns = kMs)
	{
		std::vector<struct tcs_sim_model> ms;
		for (const Spec &s : specs)
			ms.push_back(s.model());
		char err[256] = "";
		sim_ = ode()->create(ms.data(), ms.size(), step_ns, err, sizeof err);
		if (!sim_) {
			print_error("create failed: %s\n", err);
			fail();
		}
	}
	~Sim() { ode()->destroy(sim_); }
	Sim(const Sim &) = delete;
	Sim &operator=(const Sim &) = delete;

	tcs_sim *get() const { return sim_; }

	size_t index(const char *name) const
	{
		for (size_t i = 0; i < ode()->signal_count(sim_); i++)
			if (strcmp(ode()->signal_info(sim_, i)->name, name) == 0)
				return i;
		print_error("no signal %s\n", name);
		fail();
		return 0;
	}
	double get(const char *name) const
	{
		double v[7];
		assert_int_equal(ode()->read(sim_, index(name), v), 0);
		return v[0];
	}
	std::vector<double> values(const char *name) const
	{
		size_t i = index(name);
		std::vector<double> v(ode()->signal_info(sim_, i)->width);
		assert_int_equal(ode()->read(sim_, i, v.data()), 0);
		return v;
	}
	int set(const char *name, double v) { return ode()->write(sim_, index(name), &v); }
	void step(int n = 1)
	{
		char err[256] = "";
		for (int i = 0; i < n; i++) {
			if (ode()->step(sim_, err, sizeof err) != 0) {
				print_error("step failed: %s\n", err);
				fail();
			}
		}
	}

private:
	tcs_sim *sim_;
};

// create()'s message for a world that must be refused (NULL and a reason).
inline std::string create_error(std::initializer_list<Spec> specs, int64_t step_ns = kMs)
{
	std::vector<struct tcs_sim_model> ms;
	for (const Spec &s : specs)
		ms.push_back(s.model());
	char err[256] = "";
	tcs_sim *sim = ode()->create(ms.data(), ms.size(), step_ns, err, sizeof err);
	if (sim) {
		ode()->destroy(sim);
		print_error("create succeeded, expected an error\n");
		fail();
	}
	assert_true(err[0] != 0);
	assert_null(strchr(err, '\n')); // one line: the caller adds file:line
	return err;
}

inline void expect_contains(const std::string &text, const char *part)
{
	if (text.find(part) == std::string::npos) {
		print_error("'%s' does not contain '%s'\n", text.c_str(), part);
		fail();
	}
}

} // namespace simhost_checks
