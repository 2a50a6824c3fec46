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

// The robot's wires (DESIGN §9): buses the controller reaches through
// SocketCAN, a tty or /dev/i2c-N, and the devices on them.
struct CanMotorSpec {
	std::string protocol = "mit"; // the only one
	uint32_t id = 0;              // 1..0x7FF, unique on its bus
	uint32_t reply_id = 0;        // the CAN id its replies go out on (the master's)
	SignalRef joint;              // "<model>.<joint>": it drives <joint>.effort
	double position_range = 12.5, velocity_range = 50, torque_range = 5, kp_max = 500, kd_max = 5;
	int line = 0; // of [[can.motor]]
};

struct CanFieldSpec {
	SignalRef signal;         // "<model>.<part>.<field>[index]": a sensor frame's value, or an effort a command sets
	std::string type = "int16"; // int8 int16 int32 uint8 uint16 uint32 float32
	double scale = 1, offset = 0;
	int start = 0;  // byte: as written, else where the field before it ends
	int line = 0;
};

struct CanFrameSpec {
	uint32_t id = 0;
	bool extended = false;
	bool command = false;     // false: the world sends it at `rate`; true: the controller sends it, its fields set efforts
	double rate_hz = 0;       // sensor frames only
	int64_t period_ns = 0;
	bool big_endian = false;  // byte_order = "big"
	std::vector<CanFieldSpec> fields;
	int line = 0; // of [[can.frame]]
};

struct CanSpec {
	std::string interface;     // "can0": up to 15 characters, unique
	int64_t bitrate = 1000000; // bit/s
	int64_t data_bitrate = 0;  // CAN FD's data phase; 0: not FD
	std::vector<CanMotorSpec> motors;
	std::vector<CanFrameSpec> frames;
	int line = 0; // of [[can]]
};

struct ServoSpec {
	std::string protocol = "dynamixel2"; // the only one
	uint32_t id = 1;                     // 0..252, unique on its line
	SignalRef joint;
	int line = 0; // of [[serial.servo]]
};

struct SerialSpec {
	std::string path;        // absolute, normal, unique among every device path
	int64_t baud = 57600;    // the devices' rate (what the controller must set)
	std::vector<ServoSpec> servos;
	int line = 0; // of [[serial]]
};

struct I2cDeviceSpec {
	uint32_t address = 0x68;       // 7-bit, 0x03..0x77, unique on its bus
	std::string chip = "mpu6050";  // the only one
	SignalRef link;                // "<model>.<link>": its pose and twist drive the chip
	double accel_noise = 0, gyro_noise = 0; // standard deviations (m/s², rad/s)
	int line = 0; // of [[i2c.device]]
};

struct I2cSpec {
	int bus = 1;               // /dev/i2c-<bus>, unique
	int64_t clock_hz = 400000; // 100 kHz or 400 kHz (any from 10 kHz to 3.4 MHz)
	std::vector<I2cDeviceSpec> devices;
	int line = 0; // of [[i2c]]
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
	std::vector<CanSpec> cans;
	std::vector<SerialSpec> serials;
	std::vector<I2cSpec> i2cs;
	std::vector<ControllerEntry> controllers;
};

// Reads and checks a scenario. Every error reads "FILE:LINE: what is wrong".
Result<Scenario> parse_scenario_file(const std::string &path);
// The same for text in memory; name_for_errors stands for FILE. Relative
// model paths stay as written: there is no folder to resolve them against.
Result<Scenario> parse_scenario_text(const std::string &text, const std::string &name_for_errors);

// Checks every name of the scenario against the signal names of the world
// actually built (the plug-in's list), the first in the file reported: a
// signal (a device's, a sensor model's, a CAN field's without its index),
// a motor's or servo's joint J (J.position, J.velocity, J.effort), an I2C
// chip's link L (L.pose, L.twist): "FILE:LINE: unknown signal 'x' (model
// 'm' has: ...)", "unknown joint 'm.j' (model 'm' has: m.hinge)".
Status check_signals(const Scenario &scenario, const std::vector<std::string> &known);

// "FILE:LINE: what" as an Error: for later checks on a parsed scenario.
Error scenario_error(const Scenario &scenario, int line, const std::string &what);

} // namespace tcs
