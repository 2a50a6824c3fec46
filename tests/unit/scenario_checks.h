// What the scenario tests share: a text that must parse, a text whose
// error must be exactly "t.toml:LINE: ...", and the valid start of a
// scenario that each case adds lines to. Include after <cmocka.h>.
#pragma once

#include <string>
#include <utility>

#include "scenario.h"

namespace scenario_checks {

inline tcs::Scenario parse_ok(const std::string &text)
{
	auto r = tcs::parse_scenario_text(text, "t.toml");
	if (!r.ok()) {
		print_error("unexpected error: %s\n", r.error().message.c_str());
		fail();
	}
	return std::move(*r);
}

// The message is exactly "t.toml:LINE: " followed by text containing `what`.
inline void expect_error(const std::string &text, int line, const std::string &what)
{
	auto r = tcs::parse_scenario_text(text, "t.toml");
	if (r.ok()) {
		print_error("expected an error at line %d (%s), but it parsed:\n%s\n", line, what.c_str(), text.c_str());
		fail();
	}
	const std::string &msg = r.error().message;
	std::string prefix = "t.toml:" + std::to_string(line) + ": ";
	if (msg.compare(0, prefix.size(), prefix) != 0 || msg.find(what, prefix.size()) == std::string::npos ||
	    msg.find('\n') != std::string::npos) {
		print_error("got     \"%s\"\nexpected \"%s...%s...\"\n", msg.c_str(), prefix.c_str(), what.c_str());
		fail();
	}
}

// A valid scenario with one pendulum, to which each test adds a few lines
// (at line 3 and on).
inline const std::string kHead = "[sim]\nmodel = \"pendulum\"\n";

inline const std::string kSensor = "[[device]]\n"
				   "path = \"/dev/s\"\n"
				   "kind = \"sensor\"\n"
				   "signals = [\"pendulum.hinge.position\"]\n"
				   "rate = \"1kHz\"\n";

} // namespace scenario_checks
