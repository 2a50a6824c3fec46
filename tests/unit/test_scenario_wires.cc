// Unit tests for a scenario's serial lines and I2C buses
// (scenario_serial.cc, scenario_i2c.cc), for one driver an effort across
// every kind of wire (scenario_drivers.cc), and for the check of the wires'
// joints, links and signals against a world's (check_signals): accepted
// and refused, with the exact FILE:LINE of each complaint. [[can]] is
// test_scenario_can.cc's.
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

#include "scenario.h"
#include "scenario_checks.h"

namespace {

using namespace scenario_checks;
using tcs::Scenario;

// A line at lines 3 to 5 and a servo on it at 6 to 9.
const std::string kSerial = kHead + "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 57600\n";
const std::string kServo = "[[serial.servo]]\nprotocol = \"dynamixel2\"\nid = 1\njoint = \"pendulum.hinge\"\n";
// A bus at lines 3 and 4 and a chip on it at 5 to 8.
const std::string kI2c = kHead + "[[i2c]]\nbus = 1\n";
const std::string kChip = "[[i2c.device]]\naddress = 0x68\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n";

// ---- serial lines ----------------------------------------------------------------------

void test_serial(void **)
{
	Scenario s = parse_ok(kSerial + kServo);
	assert_int_equal(s.serials.size(), 1);
	const tcs::SerialSpec &l = s.serials[0];
	assert_string_equal(l.path.c_str(), "/dev/ttyUSB0");
	assert_int_equal(l.baud, 57600);
	assert_int_equal(l.line, 3);
	assert_int_equal(l.servos.size(), 1);
	assert_string_equal(l.servos[0].protocol.c_str(), "dynamixel2");
	assert_int_equal(l.servos[0].id, 1);
	assert_string_equal(l.servos[0].joint.name.c_str(), "pendulum.hinge");
	assert_int_equal(l.servos[0].joint.line, 9);
	assert_int_equal(l.servos[0].line, 6);
	// Any rate BOTHER sets from 300 on, termios's named ones below; a line
	// with no servo; servo ids 0 and 252; a second line's ids its own.
	for (int64_t baud : { 50, 75, 110, 134, 150, 200, 300, 301, 1000000, 4000000 })
		assert_int_equal(parse_ok(kHead + "[[serial]]\npath = \"/dev/ttyS0\"\nbaud = " + std::to_string(baud) + "\n")
					 .serials[0]
					 .baud,
				 baud);
	s = parse_ok(kSerial + "[[serial.servo]]\nprotocol = \"dynamixel2\"\nid = 0\njoint = \"pendulum.a\"\n"
			       "[[serial.servo]]\nprotocol = \"dynamixel2\"\nid = 252\njoint = \"pendulum.b\"\n"
			       "[[serial]]\npath = \"/dev/ttyUSB1\"\nbaud = 1000000\n"
			       "[[serial.servo]]\nprotocol = \"dynamixel2\"\nid = 0\njoint = \"pendulum.c\"\n");
	assert_int_equal(s.serials[0].servos[1].id, 252);
	assert_int_equal(s.serials[1].servos[0].id, 0);
	assert_int_equal(s.serials[1].line, 14);
}

void test_serial_refused(void **)
{
	expect_error(kHead + "[[serial]]\nbaud = 57600\n", 3, "[[serial]] needs 'path'");
	expect_error(kHead + "[[serial]]\npath = \"/dev/ttyUSB0\"\n", 3, "[[serial]] needs 'baud'");
	// A line with servos on it runs at a rate they take (without, any).
	expect_error(kHead + "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 38400\n" + kServo, 5,
		     "baud 38400 is not a rate of a Dynamixel X servo (9600, 57600, 115200, 1000000, 2000000, 3000000 or "
		     "4000000)");
	assert_int_equal(parse_ok(kHead + "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 38400\n").serials[0].baud, 38400);
	expect_error(kSerial + "parity = \"none\"\n", 6, "unknown key 'parity' in [[serial]] (known: path, baud, servo)");
	for (int64_t baud : { 0, 49, 100, 250, 299, 4000001, -9600 })
		expect_error(kHead + "[[serial]]\npath = \"/dev/ttyS0\"\nbaud = " + std::to_string(baud) + "\n", 5,
			     "baud " + std::to_string(baud) +
				     " is not a rate a serial line takes (50, 75, 110, 134, 150, 200, or 300 to 4000000)");
	expect_error(kHead + "[[serial]]\npath = \"/dev/ttyS0\"\nbaud = \"57600\"\n", 5,
		     "baud must be an integer such as 57600, not a string");
	expect_error(kHead + "[[serial]]\npath = \"/dev/ttyS0\"\nbaud = 57600.0\n", 5, "baud must be an integer");
	for (const char *bad : { "dev/ttyS0", "/dev//ttyS0", "/dev/ttyS0/", "/dev/../ttyS0", "/" })
		expect_error(kHead + "[[serial]]\npath = \"" + bad + "\"\nbaud = 57600\n", 4,
			     "serial path '" + std::string(bad) + "' must be absolute and normal");
	expect_error(kHead + "[[serial]]\npath = 1\nbaud = 57600\n", 4, "path must be a string such as \"/dev/ttyUSB0\"");
	// One path, one owner: [[device]] and [[serial]] alike.
	expect_error(kSerial + "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 9600\n", 7,
		     "path '/dev/ttyUSB0' is already the [[serial]] at line 3");
	expect_error(kHead + "[[device]]\npath = \"/dev/ttyUSB0\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n"
			     "mode = \"latest\"\n[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 9600\n",
		     9, "path '/dev/ttyUSB0' is already the [[device]] at line 3");
	expect_error(kHead + "[serial]\npath = \"/dev/ttyUSB0\"\n", 3, "'serial' must be written [[serial]]");
	expect_error(kSerial + "servo = { id = 1 }\n", 6, "'servo' must be written [[serial.servo]]");
}

void test_servos_refused(void **)
{
	const std::string v = kSerial + "[[serial.servo]]\n"; // the servo at line 6
	expect_error(v + "id = 1\njoint = \"pendulum.hinge\"\n", 6, "[[serial.servo]] needs 'protocol'");
	expect_error(v + "protocol = \"dynamixel2\"\njoint = \"pendulum.hinge\"\n", 6, "[[serial.servo]] needs 'id'");
	expect_error(v + "protocol = \"dynamixel2\"\nid = 1\n", 6, "[[serial.servo]] needs 'joint'");
	expect_error(v + "protocol = \"dynamixel1\"\nid = 1\njoint = \"pendulum.hinge\"\n", 7,
		     "unknown protocol 'dynamixel1' (known: dynamixel2)");
	expect_error(v + "protocol = \"dynamixel2\"\nid = 253\njoint = \"pendulum.hinge\"\n", 8,
		     "id 253 is out of range (0 to 252; 253 is reserved and 254 the broadcast id)");
	expect_error(v + "protocol = \"dynamixel2\"\nid = -1\njoint = \"pendulum.hinge\"\n", 8, "id -1 is out of range");
	expect_error(v + "protocol = \"dynamixel2\"\nid = true\njoint = \"pendulum.hinge\"\n", 8,
		     "id must be an integer such as 1, not a boolean");
	expect_error(kSerial + kServo + "[[serial.servo]]\nprotocol = \"dynamixel2\"\nid = 1\njoint = \"pendulum.b\"\n", 12,
		     "servo id 1 is already used on /dev/ttyUSB0 at line 6");
	expect_error(v + "protocol = \"dynamixel2\"\nid = 1\njoint = \"pendulum\"\n", 9, "joint 'pendulum' is not <model>.<joint>");
	expect_error(v + "protocol = \"dynamixel2\"\nid = 1\njoint = \"cart.slider\"\n", 9,
		     "joint 'cart.slider': the scenario has no model 'cart' (models: pendulum)");
	expect_error(kSerial + kServo + "baud = 1\n", 10,
		     "unknown key 'baud' in [[serial.servo]] (known: protocol, id, joint)");
	expect_error(kSerial + kServo + "[[serial.servo]]\nprotocol = \"dynamixel2\"\nid = 2\njoint = \"pendulum.hinge\"\n", 13,
		     "joint 'pendulum.hinge' is already driven by servo 1 on /dev/ttyUSB0 (line 9)");
}

// ---- I2C buses -------------------------------------------------------------------------

void test_i2c(void **)
{
	Scenario s = parse_ok(kI2c + kChip);
	assert_int_equal(s.i2cs.size(), 1);
	const tcs::I2cSpec &b = s.i2cs[0];
	assert_int_equal(b.bus, 1);
	assert_int_equal(b.clock_hz, 400000);
	assert_int_equal(b.line, 3);
	const tcs::I2cDeviceSpec &d = b.devices.at(0);
	assert_int_equal(d.address, 0x68);
	assert_string_equal(d.chip.c_str(), "mpu6050");
	assert_string_equal(d.link.name.c_str(), "pendulum.rod");
	assert_int_equal(d.link.line, 8);
	assert_int_equal(d.line, 5);
	assert_true(d.accel_noise == 0 && d.gyro_noise == 0);
	s = parse_ok(kHead + "[[i2c]]\nbus = 0\nclock = \"100kHz\"\n"
			     "[[i2c.device]]\naddress = 0x69\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\naccel_noise = 0.05\n"
			     "gyro_noise = 1e-3\n"
			     "[[i2c.device]]\naddress = 0x68\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n"
			     "[[i2c]]\nbus = 255\nclock = 3400000\n");
	assert_int_equal(s.i2cs[0].clock_hz, 100000);
	assert_true(s.i2cs[0].devices[0].accel_noise == 0.05 && s.i2cs[0].devices[0].gyro_noise == 1e-3);
	assert_int_equal(s.i2cs[0].devices[1].address, 0x68);
	assert_int_equal(s.i2cs[1].bus, 255);
	assert_int_equal(s.i2cs[1].clock_hz, 3400000);
	assert_true(s.i2cs[1].devices.empty()); // i2cdetect finds nothing there
	for (auto [text, hz] : { std::pair{ "\"3.4MHz\"", 3400000 }, { "\"10kHz\"", 10000 }, { "\"1 MHz\"", 1000000 },
				 { "10000", 10000 } })
		assert_int_equal(parse_ok(kI2c + "clock = " + text + "\n").i2cs[0].clock_hz, hz);
}

void test_i2c_refused(void **)
{
	expect_error(kHead + "[[i2c]]\nclock = \"400kHz\"\n", 3, "[[i2c]] needs 'bus' (N of /dev/i2c-N)");
	expect_error(kHead + "[[i2c]]\nbus = 256\n", 4, "bus 256 is out of range (0 to 255)");
	expect_error(kHead + "[[i2c]]\nbus = -1\n", 4, "bus -1 is out of range");
	expect_error(kHead + "[[i2c]]\nbus = \"1\"\n", 4, "bus must be an integer such as 1, not a string");
	expect_error(kI2c + "[[i2c]]\nbus = 1\n", 6, "bus 1 is already declared at line 3");
	expect_error(kI2c + "speed = 1\n", 5, "unknown key 'speed' in [[i2c]] (known: bus, clock, device)");
	expect_error(kI2c + "clock = \"5kHz\"\n", 5, "clock '5kHz' is out of range (10 kHz to 3.4 MHz)");
	expect_error(kI2c + "clock = 4000000\n", 5, "clock 4000000 is out of range (10 kHz to 3.4 MHz)");
	expect_error(kI2c + "clock = \"400\"\n", 5, "clock: '400' needs a unit (Hz, kHz or MHz)");
	expect_error(kI2c + "clock = \"0.4Hz\"\n", 5, "clock: '0.4Hz' is below 1 Hz");
	expect_error(kI2c + "clock = 4e5\n", 5, "clock must be a string such as \"400kHz\" or an integer (Hz), not a float");
	// /dev/i2c-N is a path like any device's.
	expect_error(kHead + "[[device]]\npath = \"/dev/i2c-1\"\nkind = \"sensor\"\nsignals = [\"pendulum.hinge.position\"]\n"
			     "mode = \"latest\"\n[[i2c]]\nbus = 1\n",
		     9, "/dev/i2c-1 is already the [[device]] at line 3");
	expect_error(kHead + "[[serial]]\npath = \"/dev/i2c-7\"\nbaud = 9600\n[[i2c]]\nbus = 7\n", 7,
		     "/dev/i2c-7 is already the [[serial]] at line 3");
	expect_error(kHead + "[i2c]\nbus = 1\n", 3, "'i2c' must be written [[i2c]]");
	expect_error(kI2c + "[i2c.device]\naddress = 0x68\n", 5, "'device' must be written [[i2c.device]]");
}

void test_i2c_chips_refused(void **)
{
	const std::string c = kI2c + "[[i2c.device]]\n"; // the chip at line 5
	expect_error(c + "chip = \"mpu6050\"\nlink = \"pendulum.rod\"\n", 5, "[[i2c.device]] needs 'address'");
	expect_error(c + "address = 0x68\nlink = \"pendulum.rod\"\n", 5, "[[i2c.device]] needs 'chip'");
	expect_error(c + "address = 0x68\nchip = \"mpu6050\"\n", 5, "[[i2c.device]] needs 'link'");
	expect_error(c + "address = 0x78\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n", 6,
		     "address 0x78 is out of range (0x03 to 0x77, the 7-bit addresses not reserved)");
	expect_error(c + "address = 2\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n", 6, "address 0x02 is out of range");
	expect_error(c + "address = -3\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n", 6, "address -3 is out of range");
	expect_error(c + "address = \"0x68\"\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n", 6,
		     "address must be an integer such as 0x68, not a string");
	expect_error(kI2c + kChip + kChip, 10, "address 0x68 is already used on /dev/i2c-1 at line 5");
	expect_error(c + "address = 0x68\nchip = \"bmi088\"\nlink = \"pendulum.rod\"\n", 7,
		     "unknown chip 'bmi088' (known: mpu6050)");
	expect_error(c + "address = 0x50\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n", 6,
		     "an mpu6050 answers at 0x68 or 0x69 (its AD0 pin), not 0x50");
	expect_error(c + "address = 0x68\nchip = \"mpu6050\"\nlink = \"pendulum\"\n", 8, "link 'pendulum' is not <model>.<link>");
	expect_error(c + "address = 0x68\nchip = \"mpu6050\"\nlink = \"arm.base\"\n", 8,
		     "link 'arm.base': the scenario has no model 'arm' (models: pendulum)");
	expect_error(kI2c + kChip + "accel_noise = -0.1\n", 9, "accel_noise must be a standard deviation >= 0, in m/s\xc2\xb2");
	expect_error(kI2c + kChip + "gyro_noise = -1\n", 9, "gyro_noise must be a standard deviation >= 0, in rad/s");
	expect_error(kI2c + kChip + "gyro_noise = nan\n", 9, "gyro_noise must be a finite number");
	expect_error(kI2c + kChip + "temp_noise = 1\n", 9,
		     "unknown key 'temp_noise' in [[i2c.device]] (known: address, chip, link, accel_noise, gyro_noise)");
	// Two chips on one link (a redundant IMU) are fine.
	parse_ok(kI2c + kChip + "[[i2c.device]]\naddress = 0x69\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n");
}

// ---- one driver an effort, across wires --------------------------------------------------

void test_one_driver(void **)
{
	const std::string can = "[[can]]\ninterface = \"can0\"\nbitrate = \"1M\"\n";
	const std::string motor = "[[can.motor]]\nprotocol = \"mit\"\nid = 1\njoint = \"pendulum.hinge\"\n";
	// A motor (its joint at line 9), then a servo on the same joint.
	expect_error(kHead + can + motor + "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 57600\n" + kServo, 16,
		     "joint 'pendulum.hinge' is already driven by motor 0x001 on can0 (line 9)");
	// A command frame's field (line 10), then a servo.
	expect_error(kHead + can + "[[can.frame]]\nid = 5\ncommand = true\nbyte_order = \"little\"\n"
				   "fields = [{ signal = \"pendulum.hinge.effort\", type = \"float32\" }]\n"
				   "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 57600\n" + kServo,
		     17, "joint 'pendulum.hinge' is already driven by command frame 0x005 on can0 (line 10)");
	// An actuator device (line 6), then a servo; a sensor device is no driver.
	const std::string device = "[[device]]\npath = \"/dev/a\"\nkind = \"actuator\"\nsignals = [\"pendulum.hinge.effort\"]\n";
	expect_error(kHead + device + "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 57600\n" + kServo, 13,
		     "joint 'pendulum.hinge' is already driven by /dev/a (line 6)");
	parse_ok(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nmode = \"latest\"\nsignals = [\"pendulum.hinge.effort\"]\n" +
		 can + motor + "[[serial]]\npath = \"/dev/ttyUSB0\"\nbaud = 57600\n" +
		 "[[serial.servo]]\nprotocol = \"dynamixel2\"\nid = 1\njoint = \"pendulum.other\"\n");
	// The device's claim is on a universal joint's whole effort: an axis of it too.
	expect_error(kHead + "[[device]]\npath = \"/dev/a\"\nkind = \"actuator\"\nsignals = [\"pendulum.u.effort\"]\n" + can +
			     "[[can.frame]]\nid = 5\ncommand = true\nbyte_order = \"little\"\n"
			     "fields = [{ signal = \"pendulum.u.effort[1]\", type = \"float32\" }]\n",
		     14, "signal 'pendulum.u.effort[1]' is already driven by /dev/a (line 6)");
}

// ---- against the world's signals ---------------------------------------------------------

const std::vector<std::string> kWorld = { "pendulum.hinge.position", "pendulum.hinge.velocity", "pendulum.hinge.effort",
					  "pendulum.rod.pose", "pendulum.rod.twist" };

void expect_unknown(const std::string &text, const std::vector<std::string> &world, const std::string &message)
{
	Scenario s = parse_ok(text);
	auto st = tcs::check_signals(s, world);
	if (st.ok()) {
		print_error("expected \"%s\", but the signals were all found\n", message.c_str());
		fail();
	}
	assert_string_equal(st.error().message.c_str(), message.c_str());
}

void test_check_signals(void **)
{
	const std::string can = "[[can]]\ninterface = \"can0\"\nbitrate = \"1M\"\n";
	const std::string good = kHead + can + "[[can.motor]]\nprotocol = \"mit\"\nid = 1\njoint = \"pendulum.hinge\"\n" +
				 "[[can.frame]]\nid = 2\nrate = \"1kHz\"\nbyte_order = \"big\"\nfields = [\n"
				 "{ signal = \"pendulum.rod.pose[3]\", type = \"float32\" },\n"
				 "{ signal = \"pendulum.hinge.velocity\", type = \"int16\" }]\n" +
				 "[[i2c]]\nbus = 1\n" + "[[i2c.device]]\naddress = 0x68\nchip = \"mpu6050\"\nlink = \"pendulum.rod\"\n";
	assert_true(tcs::check_signals(parse_ok(good), kWorld).ok());
	// A joint needs its position, velocity and effort; a link its pose and twist.
	expect_unknown(kHead + can + "[[can.motor]]\nprotocol = \"mit\"\nid = 1\njoint = \"pendulum.hing\"\n", kWorld,
		       "t.toml:9: unknown joint 'pendulum.hing' (model 'pendulum' has: pendulum.hinge)");
	expect_unknown(kHead + can + "[[can.motor]]\nprotocol = \"mit\"\nid = 1\njoint = \"pendulum.rod\"\n", kWorld,
		       "t.toml:9: unknown joint 'pendulum.rod' (model 'pendulum' has: pendulum.hinge)");
	expect_unknown(kSerial + kServo, { "pendulum.hinge.position", "pendulum.hinge.velocity", "pendulum.rod.pose" },
		       "t.toml:9: unknown joint 'pendulum.hinge' (model 'pendulum' has no joints)");
	expect_unknown(kI2c + "[[i2c.device]]\naddress = 0x68\nchip = \"mpu6050\"\nlink = \"pendulum.hinge\"\n", kWorld,
		       "t.toml:8: unknown link 'pendulum.hinge' (model 'pendulum' has: pendulum.rod)");
	expect_unknown(kI2c + kChip, { "pendulum.rod.pose", "other.rod.twist" },
		       "t.toml:8: unknown link 'pendulum.rod' (model 'pendulum' has no links)");
	// A field's signal, indexed or not.
	expect_unknown(kHead + can + "[[can.frame]]\nid = 2\nrate = \"1kHz\"\nbyte_order = \"big\"\nfields = [\n"
				     "{ signal = \"pendulum.hinge.position\", type = \"int16\" },\n"
				     "{ signal = \"pendulum.link.pose[1]\", type = \"int16\" }]\n",
		       kWorld,
		       "t.toml:12: unknown signal 'pendulum.link.pose[1]' (model 'pendulum' has: pendulum.hinge.position, "
		       "pendulum.hinge.velocity, pendulum.hinge.effort, pendulum.rod.pose, pendulum.rod.twist)");
	// Of several unknown, the first in the file, whatever its table.
	expect_unknown(kHead + "[[sensor]]\nsignal = \"pendulum.elbow.position\"\n" + kI2c.substr(kHead.size()) +
			       "[[i2c.device]]\naddress = 0x68\nchip = \"mpu6050\"\nlink = \"pendulum.arm\"\n" +
			       "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nmode = \"latest\"\nsignals = [\"pendulum.x.pose\"]\n",
		       kWorld, "t.toml:4: unknown signal 'pendulum.elbow.position' (model 'pendulum' has: "
			       "pendulum.hinge.position, pendulum.hinge.velocity, pendulum.hinge.effort, pendulum.rod.pose, "
			       "pendulum.rod.twist)");
	expect_unknown(kHead + "[[device]]\npath = \"/dev/s\"\nkind = \"sensor\"\nmode = \"latest\"\nsignals = [\"pendulum.x.pose\"]\n" +
			       "[[i2c]]\nbus = 1\n[[i2c.device]]\naddress = 0x68\nchip = \"mpu6050\"\nlink = \"pendulum.arm\"\n",
		       kWorld,
		       "t.toml:7: unknown signal 'pendulum.x.pose' (model 'pendulum' has: pendulum.hinge.position, "
		       "pendulum.hinge.velocity, pendulum.hinge.effort, pendulum.rod.pose, pendulum.rod.twist)");
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_serial),
		cmocka_unit_test(test_serial_refused),
		cmocka_unit_test(test_servos_refused),
		cmocka_unit_test(test_i2c),
		cmocka_unit_test(test_i2c_refused),
		cmocka_unit_test(test_i2c_chips_refused),
		cmocka_unit_test(test_one_driver),
		cmocka_unit_test(test_check_signals),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
