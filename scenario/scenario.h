// What a scenario file describes — the world's models, the simulation step,
// the virtual devices and optionally the controllers — checked and ready for
// the coordinator. Everything keeps the line it came from, so that whoever
// finds a problem later (the simulation plug-in refusing a parameter, a
// signal the world does not have) can still say FILE:LINE: what is wrong.
// The built-in world is default_scenario.h's.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "error.h"
#include "scenario_units.h"

namespace tcs {

struct Sim {
	int64_t step_ns = 1000000; // 1 ms; between 10 us and 1 s
	int line = 0;              // of `step`, else of [sim], else 0 (not written)
	bool step_given = false;   // `step` written (else a world file's step may stand)
};

struct ModelParam {
	std::string key;
	double value = 0;
	int line = 0;
};

// One model instance: `name` prefixes its signals ("<name>.<joint>.position").
// The type is checked against the simulation plug-in later, not here.
struct ModelSpec {
	std::string name; // an identifier, unique in the scenario
	std::string type; // "pendulum", ..., or an .sdf/.urdf path (relative ones
			  // resolved against the scenario file's folder)
	std::vector<ModelParam> params; // in file order
	int line = 0;                   // of [sim] model = ..., or of [[model]]
};

struct SignalRef {
	std::string name; // "<model>.<part>.<field>"
	int line = 0;
};

struct DeviceSpec {
	enum class Kind { Sensor, Actuator };
	enum class Format { Text, Binary };
	enum class Mode { Stream, Latest };

	std::string path; // absolute, normal (no ., .., // or trailing /)
	Kind kind = Kind::Sensor;
	std::vector<SignalRef> signals; // at least one; an actuator's are efforts
	Format format = Format::Text;
	Mode mode = Mode::Stream;    // sensors only
	double rate_hz = 0;          // sensors in stream mode only, else 0
	int64_t period_ns = 0;       // 1/rate_hz rounded to the ns, else 0
	std::optional<double> limit; // actuators only: saturation (> 0) in the signal's unit
	int line = 0;                // of [[device]]
};

// A sensor model on a signal (DESIGN §8): what a read of it sees is the
// value `latency` ago, plus bias and Gaussian noise (seeded: --seed),
// quantised to `resolution`, sampled at `rate` and held between samples.
struct SensorModelSpec {
	SignalRef signal;
	double noise = 0;      // standard deviation, in the signal's unit
	double bias = 0;
	double resolution = 0; // 0: not quantised
	int64_t latency_ns = 0;
	double rate_hz = 0; // 0: the signal's own (a robot file sensor's update_rate), else every step
	int line = 0;       // of [[sensor]]
};

struct ControllerEntry {
	std::string command;           // as written
	std::vector<std::string> argv; // command split: argv[0] is the program, unresolved
	std::optional<double> cpu_scale;
	int line = 0; // of [[controller]]
};

struct Scenario {
	std::string file; // as given, for messages
	Sim sim;
	std::vector<ModelSpec> models; // at least one
	std::vector<DeviceSpec> devices;
	std::vector<SensorModelSpec> sensors;
	std::vector<ControllerEntry> controllers;
};

// Reads and checks a scenario. Every error reads "FILE:LINE: what is wrong".
Result<Scenario> parse_scenario_file(const std::string &path);
// The same for text in memory; name_for_errors stands for FILE. Relative
// model paths stay as written: there is no folder to resolve them against.
Result<Scenario> parse_scenario_text(const std::string &text, const std::string &name_for_errors);

// Checks every device signal against the signal names of the world actually
// built (the plug-in's list): "FILE:LINE: unknown signal 'x' (model 'm' has: ...)".
Status check_signals(const Scenario &scenario, const std::vector<std::string> &known);

// "FILE:LINE: what" as an Error: for later checks on a parsed scenario.
Error scenario_error(const Scenario &scenario, int line, const std::string &what);

} // namespace tcs
