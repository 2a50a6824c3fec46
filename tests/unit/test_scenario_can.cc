// Unit tests for a scenario's [[can]] tables (scenario_can.cc,
// scenario_can_frames.cc): every rule of a bus, its motors, its frames and
// their fields, accepted and refused, with the exact FILE:LINE of each
// complaint. Serial lines, I2C buses, who drives an effort and the check
// against a world's signals are test_scenario_wires.cc's.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

extern "C" {
#include <cmocka.h>
}

#include "scenario.h"
#include "scenario_checks.h"

namespace {

using namespace scenario_checks;
using tcs::Scenario;

// A bus at lines 3 to 5, after kHead's pendulum.
const std::string kCan = kHead + "[[can]]\ninterface = \"can0\"\nbitrate = \"1Mbit/s\"\n";
// A motor at lines 6 to 9.
const std::string kMotor = "[[can.motor]]\nprotocol = \"mit\"\nid = 1\njoint = \"pendulum.hinge\"\n";

// ---- the bus ---------------------------------------------------------------------------

void test_bus(void **)
{
	Scenario s = parse_ok(kCan);
	assert_int_equal(s.cans.size(), 1);
	assert_string_equal(s.cans[0].interface.c_str(), "can0");
	assert_int_equal(s.cans[0].bitrate, 1000000);
	assert_int_equal(s.cans[0].data_bitrate, 0);
	assert_int_equal(s.cans[0].line, 3);
	assert_true(s.cans[0].motors.empty() && s.cans[0].frames.empty()); // a bus alone: programs talk on it
	s = parse_ok(kHead + "[[can]]\ninterface = \"vcan_1.x-y\"\nbitrate = 500000\ndata_bitrate = \"5Mbit/s\"\n"
			     "[[can]]\ninterface = \"can012345678901\"\nbitrate = \"83.333kbit/s\"\n");
	assert_int_equal(s.cans[0].bitrate, 500000);
	assert_int_equal(s.cans[0].data_bitrate, 5000000);
	assert_string_equal(s.cans[1].interface.c_str(), "can012345678901");
	assert_int_equal(s.cans[1].bitrate, 83333);
	assert_int_equal(s.cans[1].line, 7);
	for (auto [text, bps] : { std::pair{ "\"125 kbit/s\"", 125000 }, { "\"500k\"", 500000 }, { "\"1M\"", 1000000 },
				  { "\"10kbit/s\"", 10000 }, { "10000", 10000 }, { "\"250Kbit/s\"", 250000 } }) {
		s = parse_ok(kHead + "[[can]]\ninterface = \"can0\"\nbitrate = " + text + "\n");
		assert_int_equal(s.cans[0].bitrate, bps);
	}
	// FD's data phase: up to 8 Mbit/s, and no slower than the arbitration.
	assert_int_equal(parse_ok(kCan + "data_bitrate = 8000000\n").cans[0].data_bitrate, 8000000);
	assert_int_equal(parse_ok(kCan + "data_bitrate = \"1Mbit/s\"\n").cans[0].data_bitrate, 1000000);
}

void test_bus_refused(void **)
{
	const std::string can = kHead + "[[can]]\ninterface = \"can0\"\n";
	expect_error(kHead + "[[can]]\nbitrate = \"1Mbit/s\"\n", 3, "[[can]] needs 'interface'");
	expect_error(can, 3, "[[can]] needs 'bitrate'");
	expect_error(can + "bitrate = \"2Mbit/s\"\n", 5, "bitrate '2Mbit/s' is out of range (10 kbit/s to 1 Mbit/s)");
	expect_error(can + "bitrate = 5000\n", 5, "bitrate 5000 is out of range (10 kbit/s to 1 Mbit/s)");
	expect_error(can + "bitrate = \"9.9kbit/s\"\n", 5, "out of range");
	expect_error(can + "bitrate = \"500\"\n", 5, "bitrate: '500' needs a unit (bit/s, kbit/s or Mbit/s)");
	expect_error(can + "bitrate = \"1 Mbps\"\n", 5, "bitrate: '1 Mbps': unknown unit 'Mbps'");
	expect_error(can + "bitrate = \"fast\"\n", 5, "bitrate: 'fast' is not a bit rate");
	expect_error(can + "bitrate = 1e6\n", 5,
		     "bitrate must be a string such as \"1Mbit/s\" or an integer (bit/s), not a float");
	expect_error(kCan + "data_bitrate = \"10Mbit/s\"\n", 6,
		     "data_bitrate '10Mbit/s' is out of range (at most 8 Mbit/s, CAN FD's)");
	expect_error(kCan + "data_bitrate = \"500k\"\n", 6,
		     "data_bitrate (500 kbit/s) is below bitrate (1 Mbit/s): CAN FD's data phase is at least as fast");
	expect_error(kCan + "data_bitrate = 0\n", 6, "data_bitrate 0 is out of range");
	for (const char *bad : { "", "can0123456789012", "can 0", "can/0", ".", "..", "caf\xc3\xa9" })
		expect_error(kHead + "[[can]]\ninterface = \"" + bad + "\"\nbitrate = \"1M\"\n", 4,
			     "interface '" + std::string(bad) +
				     "' is not a network interface's name (1 to 15 of A-Z a-z 0-9 _ . -)");
	expect_error(kHead + "[[can]]\ninterface = 0\nbitrate = \"1M\"\n", 4, "interface must be a string such as \"can0\"");
	expect_error(kCan + "[[can]]\nbitrate = \"1M\"\ninterface = \"can0\"\n", 8,
		     "interface 'can0' is already declared at line 3");
	expect_error(kCan + "name = \"x\"\n", 6,
		     "unknown key 'name' in [[can]] (known: interface, bitrate, data_bitrate, motor, frame)");
	// Unknown keys come first, whatever else is wrong.
	expect_error(kHead + "[[can]]\nbitrate = 5\nspeed = 1\n", 5, "unknown key 'speed' in [[can]]");
	expect_error(kHead + "[can]\ninterface = \"can0\"\n", 3, "'can' must be written [[can]] (an array of tables)");
	expect_error(kCan + "[can.motor]\nid = 1\n", 6, "'motor' must be written [[can.motor]] (an array of tables)");
	expect_error(kCan + "frame = 3\n", 6, "'frame' must be written [[can.frame]]");
}

// ---- motors ----------------------------------------------------------------------------

void test_motors(void **)
{
	Scenario s = parse_ok(kCan + kMotor);
	const tcs::CanMotorSpec &m = s.cans[0].motors.at(0);
	assert_string_equal(m.protocol.c_str(), "mit");
	assert_int_equal(m.id, 1);
	assert_int_equal(m.reply_id, 0);
	assert_string_equal(m.joint.name.c_str(), "pendulum.hinge");
	assert_int_equal(m.joint.line, 9);
	assert_int_equal(m.line, 6);
	assert_true(m.position_range == 12.5 && m.velocity_range == 50 && m.torque_range == 5 && m.kp_max == 500 &&
		    m.kd_max == 5);
	s = parse_ok("[[model]]\nname = \"a\"\ntype = \"pendulum\"\n[[model]]\nname = \"b\"\ntype = \"pendulum\"\n"
		     "[[can]]\ninterface = \"can0\"\nbitrate = 1000000\n"
		     "[[can.motor]]\nprotocol = \"mit\"\nid = 0x7FF\nreply_id = 0x7FF\njoint = \"a.hinge\"\n"
		     "position_range = 95.5\nvelocity_range = 30\ntorque_range = 18\nkp_max = 5e2\nkd_max = 5.0\n"
		     "[[can.motor]]\nprotocol = \"mit\"\nid = 2\njoint = \"b.hinge\"\n");
	const tcs::CanMotorSpec &big = s.cans[0].motors.at(0);
	assert_int_equal(big.id, 0x7FF);
	assert_int_equal(big.reply_id, 0x7FF);
	assert_true(big.position_range == 95.5 && big.velocity_range == 30 && big.torque_range == 18 &&
		    big.kp_max == 500 && big.kd_max == 5);
	assert_string_equal(s.cans[0].motors.at(1).joint.name.c_str(), "b.hinge");
	// Motors on two buses may share an id.
	s = parse_ok(kCan + kMotor + "[[can]]\ninterface = \"can1\"\nbitrate = \"1M\"\n"
				     "[[can.motor]]\nprotocol = \"mit\"\nid = 1\njoint = \"pendulum.other\"\n");
	assert_int_equal(s.cans[1].motors.at(0).id, 1);
}

void test_motors_refused(void **)
{
	const std::string m = kCan + "[[can.motor]]\n"; // the motor at line 6
	expect_error(m + "id = 1\njoint = \"pendulum.hinge\"\n", 6, "[[can.motor]] needs 'protocol'");
	expect_error(m + "protocol = \"mit\"\njoint = \"pendulum.hinge\"\n", 6, "[[can.motor]] needs 'id'");
	expect_error(m + "protocol = \"mit\"\nid = 1\n", 6, "[[can.motor]] needs 'joint'");
	expect_error(m + "protocol = \"odrive\"\nid = 1\njoint = \"pendulum.hinge\"\n", 7,
		     "unknown protocol 'odrive' (known: mit)");
	expect_error(m + "protocol = 1\nid = 1\njoint = \"pendulum.hinge\"\n", 7, "protocol must be a string such as \"mit\"");
	expect_error(m + "protocol = \"mit\"\nid = 0\njoint = \"pendulum.hinge\"\n", 8, "id 0x000 is out of range (0x001 to 0x7FF)");
	expect_error(m + "protocol = \"mit\"\nid = 0x800\njoint = \"pendulum.hinge\"\n", 8,
		     "id 0x800 is out of range (0x001 to 0x7FF)");
	expect_error(m + "protocol = \"mit\"\nid = -1\njoint = \"pendulum.hinge\"\n", 8, "id -1 is out of range");
	expect_error(m + "protocol = \"mit\"\nid = 1.0\njoint = \"pendulum.hinge\"\n", 8,
		     "id must be an integer such as 0x100, not a float");
	expect_error(m + "protocol = \"mit\"\nid = \"1\"\njoint = \"pendulum.hinge\"\n", 8, "id must be an integer");
	expect_error(kCan + kMotor + "[[can.motor]]\nprotocol = \"mit\"\nid = 1\njoint = \"pendulum.other\"\n", 12,
		     "CAN id 0x001 is already used on can0 by the motor at line 6");
	expect_error(kCan + kMotor + "reply_id = 0x800\n", 10, "reply_id 0x800 is out of range (0x000 to 0x7FF)");
	expect_error(kCan + kMotor + "reply_id = -2\n", 10, "reply_id -2 is out of range");
	expect_error(kCan + kMotor + "reply_id = \"0\"\n", 10, "reply_id must be an integer such as 0, not a string");
	for (const char *bad : { "pendulum", "pendulum.", ".hinge", "pendulum..x", "pendulum.hin ge", "1.hinge" })
		expect_error(m + "protocol = \"mit\"\nid = 1\njoint = \"" + bad + "\"\n", 9,
			     "joint '" + std::string(bad) + "' is not <model>.<joint>");
	expect_error(m + "protocol = \"mit\"\nid = 1\njoint = \"arm.hinge\"\n", 9,
		     "joint 'arm.hinge': the scenario has no model 'arm' (models: pendulum)");
	expect_error(m + "protocol = \"mit\"\nid = 1\njoint = [\"pendulum.hinge\"]\n", 9,
		     "joint must be a string such as \"pendulum.hinge\", not an array");
	expect_error(kCan + kMotor + "torque_range = 0\n", 10,
		     "torque_range must be positive (the magnitude the protocol's field reaches at its extreme)");
	expect_error(kCan + kMotor + "kp_max = -500\n", 10, "kp_max must be positive");
	expect_error(kCan + kMotor + "kd_max = inf\n", 10, "kd_max must be a finite number");
	expect_error(kCan + kMotor + "position_range = \"12.5\"\n", 10, "position_range must be a number, not a string");
	expect_error(kCan + kMotor + "current_range = 1\n", 10,
		     "unknown key 'current_range' in [[can.motor]] (known: protocol, id, reply_id, joint, position_range, "
		     "velocity_range, torque_range, kp_max, kd_max)");
	expect_error(kCan + "[[can.motor]]\nspeed = 1\nid = 0\n", 7, "unknown key 'speed' in [[can.motor]]");
	// Two motors on one joint would each set its effort.
	expect_error(kCan + kMotor + "[[can.motor]]\nprotocol = \"mit\"\nid = 2\njoint = \"pendulum.hinge\"\n", 13,
		     "joint 'pendulum.hinge' is already driven by motor 0x001 on can0 (line 9)");
	expect_error(kHead + "[[device]]\npath = \"/dev/a\"\nkind = \"actuator\"\nsignals = [\"pendulum.hinge.effort\"]\n" +
			     "[[can]]\ninterface = \"can0\"\nbitrate = \"1M\"\n" + kMotor,
		     13, "joint 'pendulum.hinge' is already driven by /dev/a (line 6)");
}

// ---- frames ----------------------------------------------------------------------------

// A field, as an inline table.
std::string field(const std::string &signal, const std::string &type, const std::string &more = "")
{
	return "{ signal = \"" + signal + "\", type = \"" + type + "\"" + more + " }";
}

void test_frames(void **)
{
	Scenario s = parse_ok(kCan + "[[can.frame]]\nid = 0x100\nrate = \"100Hz\"\nbyte_order = \"little\"\nfields = [\n  " +
			      field("pendulum.hinge.position", "int16", ", scale = 0.001, offset = -1.5, start = 0") +
			      ",\n  " + field("pendulum.hinge.velocity", "float32") + ",\n  " +
			      field("pendulum.rod.pose[2]", "uint8", ", start = 7") + ",\n]\n");
	const tcs::CanFrameSpec &f = s.cans[0].frames.at(0);
	assert_int_equal(f.id, 0x100);
	assert_false(f.extended);
	assert_false(f.command);
	assert_true(f.rate_hz == 100);
	assert_int_equal(f.period_ns, 10000000);
	assert_false(f.big_endian);
	assert_int_equal(f.line, 6);
	assert_int_equal(f.fields.size(), 3);
	assert_string_equal(f.fields[0].signal.name.c_str(), "pendulum.hinge.position");
	assert_string_equal(f.fields[0].type.c_str(), "int16");
	assert_true(f.fields[0].scale == 0.001 && f.fields[0].offset == -1.5);
	assert_int_equal(f.fields[0].start, 0);
	assert_int_equal(f.fields[0].line, 11);
	assert_int_equal(f.fields[0].signal.line, 11);
	// Without start, a field follows the one before it.
	assert_int_equal(f.fields[1].start, 2);
	assert_true(f.fields[1].scale == 1 && f.fields[1].offset == 0);
	assert_string_equal(f.fields[2].signal.name.c_str(), "pendulum.rod.pose[2]");
	assert_int_equal(f.fields[2].start, 7);
	assert_int_equal(f.fields[2].line, 13);

	// A command frame, 29-bit, big-endian, its fields written as tables.
	s = parse_ok(kCan + "[[can.frame]]\nid = 0x1FFFFFFF\nextended = true\ncommand = true\nbyte_order = \"big\"\n"
			    "[[can.frame.fields]]\nsignal = \"pendulum.hinge.effort\"\ntype = \"int32\"\nscale = 1e-3\n");
	const tcs::CanFrameSpec &c = s.cans[0].frames.at(0);
	assert_int_equal(c.id, 0x1FFFFFFF);
	assert_true(c.extended && c.command && c.big_endian);
	assert_true(c.rate_hz == 0 && c.period_ns == 0);
	assert_int_equal(c.fields.at(0).line, 11);
	assert_int_equal(c.fields.at(0).signal.line, 12);
	// A frame with no fields at a rate (a SYNC); `command = false` is a
	// frame the world sends; id 0 is a frame's; the same number standard
	// and extended is two ids.
	s = parse_ok(kCan + "[[can.frame]]\nid = 0\nrate = \"1kHz\"\ncommand = false\nbyte_order = \"big\"\nfields = []\n"
			    "[[can.frame]]\nid = 0\nextended = true\nrate = \"1Hz\"\nbyte_order = \"little\"\nfields = []\n");
	assert_int_equal(s.cans[0].frames.size(), 2);
	assert_true(s.cans[0].frames[1].extended);
	// A sensor frame may carry an effort, and another driver's.
	parse_ok(kCan + kMotor + "[[can.frame]]\nid = 2\nrate = \"1kHz\"\nbyte_order = \"big\"\nfields = [" +
		 field("pendulum.hinge.effort", "int16") + ", " + field("pendulum.hinge.effort", "int16") + "]\n");
}

void test_frames_refused(void **)
{
	const std::string f = kCan + "[[can.frame]]\n"; // the frame at line 6
	const std::string one = "fields = [" + field("pendulum.hinge.position", "int16") + "]\n";
	expect_error(f + "rate = \"1kHz\"\nbyte_order = \"big\"\n" + one, 6, "[[can.frame]] needs 'id'");
	expect_error(f + "id = 1\nrate = \"1kHz\"\n" + one, 6, "[[can.frame]] needs 'byte_order'");
	expect_error(f + "id = 1\nrate = \"1kHz\"\nbyte_order = \"big\"\n", 6, "[[can.frame]] needs 'fields'");
	expect_error(f + "id = 1\nbyte_order = \"big\"\n" + one, 6,
		     "[[can.frame]] needs a rate (a frame the world sends, such as rate = \"100Hz\") or command = true "
		     "(a frame the controller sends)");
	expect_error(f + "id = 1\ncommand = false\nbyte_order = \"big\"\n" + one, 6, "[[can.frame]] needs a rate");
	expect_error(f + "id = 1\ncommand = true\nrate = \"1kHz\"\nbyte_order = \"big\"\n" + one, 9,
		     "'rate' applies only to a frame the world sends: a command frame (command = true) comes when the "
		     "controller sends it");
	expect_error(f + "id = 1\ncommand = 1\nbyte_order = \"big\"\n" + one, 8, "command must be true or false, not an integer");
	expect_error(f + "id = 1\nextended = \"no\"\nrate = \"1kHz\"\nbyte_order = \"big\"\n" + one, 8,
		     "extended must be true or false, not a string");
	expect_error(f + "id = 0x800\nrate = \"1kHz\"\nbyte_order = \"big\"\n" + one, 7,
		     "id 0x800 is out of range (0x000 to 0x7FF; extended = true allows 29-bit ids)");
	expect_error(f + "extended = true\nid = 0x20000000\nrate = \"1kHz\"\nbyte_order = \"big\"\n" + one, 8,
		     "id 0x20000000 is out of range (0x00000000 to 0x1FFFFFFF)");
	expect_error(f + "id = 1\nrate = \"often\"\nbyte_order = \"big\"\n" + one, 8, "rate: 'often' is not a rate");
	expect_error(f + "id = 1\nrate = 100\nbyte_order = \"big\"\n" + one, 8, "rate must be a string such as \"100Hz\"");
	expect_error(f + "id = 1\nrate = \"1kHz\"\nbyte_order = \"intel\"\n" + one, 9,
		     "byte_order must be \"little\" or \"big\", not \"intel\"");
	expect_error(f + "id = 1\nrate = \"1kHz\"\nbyte_order = \"big\"\ndlc = 8\n" + one, 10,
		     "unknown key 'dlc' in [[can.frame]] (known: id, extended, rate, command, byte_order, fields)");
	// Ids are unique on a bus among motors and frames, the later one named.
	const std::string frame1 = "[[can.frame]]\nid = 1\nrate = \"1kHz\"\nbyte_order = \"big\"\nfields = []\n";
	expect_error(kCan + kMotor + frame1, 11, "CAN id 0x001 is already used on can0 by the motor at line 6");
	expect_error(kCan + frame1 + kMotor, 13, "CAN id 0x001 is already used on can0 by the frame at line 6");
	expect_error(kCan + frame1 + frame1, 12, "CAN id 0x001 is already used on can0 by the frame at line 6");
	expect_error(kCan + "[[can.frame]]\nid = 0x10\nextended = true\nrate = \"1kHz\"\nbyte_order = \"big\"\nfields = []\n" +
			     "[[can.frame]]\nextended = true\nid = 0x10\nrate = \"1kHz\"\nbyte_order = \"big\"\nfields = []\n",
		     14, "CAN id 0x00000010 is already used on can0 by the frame at line 6");
}

void test_fields_refused(void **)
{
	// A sensor frame at line 6, its fields at line 10.
	const std::string f = kCan + "[[can.frame]]\nid = 1\nrate = \"1kHz\"\nbyte_order = \"big\"\n";
	const std::string c = kCan + "[[can.frame]]\nid = 1\ncommand = true\nbyte_order = \"big\"\n";
	expect_error(f + "fields = 3\n", 10, "fields must be an array of tables such as [ { signal = ");
	expect_error(f + "fields = [\n" + field("pendulum.hinge.position", "int16") + ",\n 3]\n", 12,
		     "fields must be tables such as { signal = \"pendulum.hinge.position\", type = \"int16\" }, not an integer");
	expect_error(c + "fields = []\n", 10, "fields is empty: a command frame sets at least one effort");
	expect_error(f + "fields = [{ type = \"int16\" }]\n", 10, "a field of [[can.frame]] needs 'signal'");
	expect_error(f + "fields = [{ signal = \"pendulum.hinge.position\" }]\n", 10, "a field of [[can.frame]] needs 'type'");
	expect_error(f + "fields = [" + field("pendulum.hinge.position", "int16", ", bits = 12") + "]\n", 10,
		     "unknown key 'bits' in a field of [[can.frame]] (known: signal, type, scale, offset, start)");
	expect_error(f + "fields = [" + field("pendulum.hinge.position", "int64") + "]\n", 10,
		     "type must be one of int8, int16, int32, uint8, uint16, uint32, float32, not \"int64\"");
	expect_error(f + "fields = [" + field("pendulum.hinge.position", "int16", ", scale = 0") + "]\n", 10,
		     "scale must not be 0");
	expect_error(f + "fields = [" + field("pendulum.hinge.position", "int16", ", offset = nan") + "]\n", 10,
		     "offset must be a finite number");
	expect_error(f + "fields = [" + field("pendulum.hinge.position", "int16", ", start = -1") + "]\n", 10,
		     "start must be a byte number >= 0");
	expect_error(f + "fields = [" + field("pendulum.hinge.position", "int16", ", start = 1.0") + "]\n", 10,
		     "start must be an integer such as 0, not a float");
	expect_error(f + "fields = [" + field("pendulum.hinge.position", "int16", ", start = 9223372036854775807") + "]\n",
		     10, "runs past");
	// The payload: 8 bytes, 64 with data_bitrate.
	expect_error(f + "fields = [\n" + field("pendulum.hinge.position", "float32", ", start = 4") + ",\n" +
			     field("pendulum.hinge.velocity", "int8") + "]\n",
		     12,
		     "field 'pendulum.hinge.velocity' (int8 at byte 8) runs past the 8 bytes of a CAN frame (an interface "
		     "with data_bitrate, CAN FD, carries 64)");
	const std::string fd = kCan + "data_bitrate = \"5M\"\n[[can.frame]]\nid = 1\nrate = \"1kHz\"\nbyte_order = \"big\"\n";
	Scenario s = parse_ok(fd + "fields = [" + field("pendulum.hinge.position", "float32", ", start = 60") + "]\n");
	assert_int_equal(s.cans[0].frames[0].fields[0].start, 60);
	expect_error(fd + "fields = [" + field("pendulum.hinge.position", "float32", ", start = 61") + "]\n", 11,
		     "field 'pendulum.hinge.position' (float32 at byte 61) runs past the 64 bytes of a CAN FD frame");
	// Written as tables, the field's place is wrong at its start, else at its table.
	const std::string tables = f + "[[can.frame.fields]]\nsignal = \"pendulum.hinge.position\"\ntype = \"int32\"\n"
				       "[[can.frame.fields]]\nsignal = \"pendulum.hinge.velocity\"\ntype = \"int16\"\n";
	expect_error(tables + "start = 2\n", 16,
		     "field 'pendulum.hinge.velocity' (bytes 2 to 3) overlaps field 'pendulum.hinge.position' (bytes 0 to 3, "
		     "line 10)");
	expect_error(tables + "[[can.frame.fields]]\nsignal = \"pendulum.rod.pose[0]\"\ntype = \"float32\"\n", 16,
		     "field 'pendulum.rod.pose[0]' (float32 at byte 6) runs past the 8 bytes");
	// Fields may not share a byte.
	expect_error(f + "fields = [\n" + field("pendulum.hinge.position", "int32") + ",\n" +
			     field("pendulum.hinge.velocity", "int16", ", start = 3") + "]\n",
		     12,
		     "field 'pendulum.hinge.velocity' (bytes 3 to 4) overlaps field 'pendulum.hinge.position' (bytes 0 "
		     "to 3, line 11)");
	expect_error(f + "fields = [\n" + field("pendulum.hinge.position", "int8", ", start = 5") + ",\n" +
			     field("pendulum.hinge.velocity", "uint16", ", start = 4") + "]\n",
		     12, "(bytes 4 to 5) overlaps field 'pendulum.hinge.position' (byte 5, line 11)");
	// "After the previous field" is after the one written before, wherever it is.
	Scenario t = parse_ok(f + "fields = [\n" + field("pendulum.hinge.position", "int8", ", start = 5") + ",\n" +
			      field("pendulum.hinge.velocity", "uint16", ", start = 0") + ", " +
			      field("pendulum.rod.pose[0]", "int8") + "]\n");
	assert_int_equal(t.cans[0].frames[0].fields[2].start, 2);
}

void test_field_signals(void **)
{
	const std::string f = kCan + "[[can.frame]]\nid = 1\nrate = \"1kHz\"\nbyte_order = \"big\"\n";
	const std::string c = kCan + "[[can.frame]]\nid = 1\ncommand = true\nbyte_order = \"big\"\n";
	expect_error(f + "fields = [" + field("pendulum.hinge", "int16") + "]\n", 10,
		     "signal 'pendulum.hinge' is not <model>.<part>.<field>");
	expect_error(f + "fields = [" + field("arm.hinge.position", "int16") + "]\n", 10,
		     "signal 'arm.hinge.position': the scenario has no model 'arm' (models: pendulum)");
	expect_error(f + "fields = [{ signal = 3, type = \"int16\" }]\n", 10, "signal must be a string");
	// A signal of several values: one of them, by its index.
	expect_error(f + "fields = [" + field("pendulum.rod.pose", "int16") + "]\n", 10,
		     "signal 'pendulum.rod.pose' has 7 values and a field carries one: pick it, as 'pendulum.rod.pose[0]'");
	expect_error(f + "fields = [" + field("pendulum.rod.twist", "int16") + "]\n", 10, "has 6 values");
	expect_error(f + "fields = [" + field("pendulum.rod.pose[7]", "int16") + "]\n", 10,
		     "signal 'pendulum.rod.pose[7]': index 7 is past the values of pose (0 to 6)");
	expect_error(f + "fields = [" + field("pendulum.hinge.position[2]", "int16") + "]\n", 10,
		     "index 2 is past the values of position (0 to 1)");
	for (const char *bad : { "pendulum.rod.pose[]", "pendulum.rod.pose[01]", "pendulum.rod.pose[x]",
				 "pendulum.rod.pose[-1]", "pendulum.rod.pose]", "pendulum.rod.pose[100]" })
		expect_error(f + "fields = [" + field(bad, "int16") + "]\n", 10,
			     "signal '" + std::string(bad) + "': an index is written [N], as in 'pendulum.rod.pose[2]'");
	Scenario s = parse_ok(f + "fields = [" + field("pendulum.rod.pose[6]", "int16") + ", " +
			      field("pendulum.hinge.position[1]", "int16") + ", " + field("pendulum.hinge.position", "int16") +
			      "]\n");
	assert_string_equal(s.cans[0].frames[0].fields[0].signal.name.c_str(), "pendulum.rod.pose[6]");
	// A command frame sets efforts, each from one driver only.
	expect_error(c + "fields = [" + field("pendulum.hinge.position", "int16") + "]\n", 10,
		     "command frame field 'pendulum.hinge.position' is not an effort: a command frame sets "
		     "<model>.<joint>.effort");
	expect_error(c + "fields = [\n" + field("pendulum.hinge.effort", "int16") + ",\n" +
			     field("pendulum.hinge.effort", "int16") + "]\n",
		     12, "signal 'pendulum.hinge.effort' is already driven by command frame 0x001 on can0 (line 11)");
	expect_error(kCan + kMotor + "[[can.frame]]\nid = 2\ncommand = true\nbyte_order = \"big\"\nfields = [" +
			     field("pendulum.hinge.effort", "int16") + "]\n",
		     14, "signal 'pendulum.hinge.effort' is already driven by motor 0x001 on can0 (line 9)");
	expect_error(kCan + "[[can.frame]]\nid = 2\nextended = true\ncommand = true\nbyte_order = \"big\"\nfields = [" +
			     field("pendulum.hinge.effort", "int16") + "]\n" + kMotor,
		     15, "joint 'pendulum.hinge' is already driven by command frame 0x00000002 on can0 (line 11)");
	// A universal joint's two axes, each from its own field; the whole
	// effort meets either.
	s = parse_ok(c + "fields = [" + field("pendulum.u.effort[0]", "int16") + ", " + field("pendulum.u.effort[1]", "int16") +
		     "]\n");
	assert_int_equal(s.cans[0].frames[0].fields.size(), 2);
	expect_error(c + "fields = [\n" + field("pendulum.u.effort[1]", "int16") + ",\n" +
			     field("pendulum.u.effort", "int16") + "]\n",
		     12, "signal 'pendulum.u.effort' is already driven by command frame 0x001 on can0 (line 11)");
	expect_error(kCan + "[[can.frame]]\nid = 2\ncommand = true\nbyte_order = \"big\"\nfields = [" +
			     field("pendulum.hinge.effort[0]", "int16") + "]\n" + kMotor,
		     14, "joint 'pendulum.hinge' is already driven by command frame 0x002 on can0 (line 10)");
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_bus),
		cmocka_unit_test(test_bus_refused),
		cmocka_unit_test(test_motors),
		cmocka_unit_test(test_motors_refused),
		cmocka_unit_test(test_frames),
		cmocka_unit_test(test_frames_refused),
		cmocka_unit_test(test_fields_refused),
		cmocka_unit_test(test_field_signals),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
