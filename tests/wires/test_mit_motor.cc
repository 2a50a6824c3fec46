// Unit tests for the MIT mini-cheetah actuator protocol (wires/can/
// mit_codec.h, mit_motor.h): known byte patterns worked out by hand from
// the protocol's linear mapping, round trips within one quantum, the torque
// law and its saturation, the special frames, zeroing, and what a motor
// ignores.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "mit_motor.h"

namespace {

using tcs::CanFrame;
using tcs::MitCommand;
using tcs::MitMotor;
using tcs::MitRanges;

CanFrame to_motor(uint32_t id, const uint8_t (&data)[8])
{
	CanFrame f;
	f.id = id;
	f.len = 8;
	memcpy(f.data, data, 8);
	return f;
}

const uint8_t kEnter[8] = { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFC };
const uint8_t kExit[8] = { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFD };
const uint8_t kZero[8] = { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFE };
// p = 1 → 13.5·65535/25 = 35388.9 → 0x8A3C; v = 2 → 52·4095/100 = 2129.4
// → 0x851; kp = 10 → 81.9 → 0x051; kd = 1 → 819 = 0x333; t = -1 → 1638 = 0x666.
const uint8_t kCommand[8] = { 0x8A, 0x3C, 0x85, 0x10, 0x51, 0x33, 0x36, 0x66 };
// What the motor makes of kCommand (the raw values mapped back).
const double kPdes = 35388 * 25.0 / 65535 - 12.5, kVdes = 2129 * 100.0 / 4095 - 50, kKp = 81 * 500.0 / 4095,
	     kKd = 1.0, kTff = -1.0;

void known_bytes(void **)
{
	MitRanges r;
	uint8_t out[8];
	tcs::mit_pack_command(r, MitCommand{}, out);
	const uint8_t zeros[8] = { 0x7F, 0xFF, 0x7F, 0xF0, 0x00, 0x00, 0x07, 0xFF };
	assert_memory_equal(out, zeros, 8);
	tcs::mit_pack_command(r, { 1, 2, 10, 1, -1 }, out);
	assert_memory_equal(out, kCommand, 8);
	// Every field at its top, v at its bottom; past the range saturates.
	tcs::mit_pack_command(r, { 12.5, -50, 500, 5, 5 }, out);
	const uint8_t tops[8] = { 0xFF, 0xFF, 0x00, 0x0F, 0xFF, 0xFF, 0xFF, 0xFF };
	assert_memory_equal(out, tops, 8);
	tcs::mit_pack_command(r, { 99, -1e9, 1e4, 6, INFINITY }, out);
	assert_memory_equal(out, tops, 8);
	// NaN is the bottom, as the firmware's fmaxf(min, x) makes it.
	tcs::mit_pack_command(r, { NAN, NAN, NAN, NAN, NAN }, out);
	const uint8_t bottoms[8] = {};
	assert_memory_equal(out, bottoms, 8);
	// Reply: id 1, p 0.5 → 13·65535/25 = 34078.2 → 0x851E, v -3 → 47·4095/100
	// = 1924.65 → 0x784, t 0.25 → 5.25·4095/10 = 2149.875 → 0x865.
	uint8_t reply[6];
	tcs::mit_pack_reply(r, { 1, 0.5, -3, 0.25 }, reply);
	const uint8_t expected[6] = { 0x01, 0x85, 0x1E, 0x78, 0x48, 0x65 };
	assert_memory_equal(reply, expected, 6);
	const tcs::MitReply back = tcs::mit_unpack_reply(r, reply);
	assert_int_equal(back.id, 1);
	assert_float_equal(back.position, 34078 * 25.0 / 65535 - 12.5, 1e-12);
	assert_float_equal(back.velocity, 1924 * 100.0 / 4095 - 50, 1e-12);
	assert_float_equal(back.torque, 2149 * 10.0 / 4095 - 5, 1e-12);
}

// decode(encode(x)) lies in (x - quantum, x]: the firmware truncates.
void within_a_quantum(double x, double got, double span, int bits)
{
	const double q = span / ((1 << bits) - 1);
	assert_true(got <= x + 1e-9 && got > x - q - 1e-9);
}

void round_trips(void **)
{
	MitRanges r;
	r.position_range = 95.5;
	r.velocity_range = 30;
	r.torque_range = 18;
	for (int i = 0; i <= 1000; i++) {
		const double u = i / 1000.0; // 0..1 across each range
		const MitCommand c{ -95.5 + 191 * u, -30 + 60 * u, 500 * u, 5 * u, -18 + 36 * u };
		uint8_t out[8];
		tcs::mit_pack_command(r, c, out);
		const MitCommand d = tcs::mit_unpack_command(r, out);
		within_a_quantum(c.position, d.position, 191, 16);
		within_a_quantum(c.velocity, d.velocity, 60, 12);
		within_a_quantum(c.kp, d.kp, 500, 12);
		within_a_quantum(c.kd, d.kd, 5, 12);
		within_a_quantum(c.torque, d.torque, 36, 12);
		uint8_t reply[6];
		tcs::mit_pack_reply(r, { 7, c.position, c.velocity, c.torque }, reply);
		const tcs::MitReply b = tcs::mit_unpack_reply(r, reply);
		assert_int_equal(b.id, 7);
		within_a_quantum(c.position, b.position, 191, 16);
		within_a_quantum(c.velocity, b.velocity, 60, 12);
		within_a_quantum(c.torque, b.torque, 36, 12);
	}
}

void torque_law(void **)
{
	MitMotor m(1);
	std::string note;
	assert_true(m.receive(to_motor(1, kEnter), 0, 0, 0, &note).has_value());
	assert_true(m.enabled());
	assert_float_equal(m.torque(0.9, 1.9), 0, 0); // no command yet
	assert_true(m.receive(to_motor(1, kCommand), 0.9, 1.9, 0, &note).has_value());
	const double expected = kKp * (kPdes - 0.9) + kKd * (kVdes - 1.9) + kTff;
	assert_true(std::fabs(expected) < 5);
	assert_float_equal(m.torque(0.9, 1.9), expected, 1e-12);
	// Saturated at ±torque_range.
	assert_float_equal(m.torque(-1, 0), 5, 0);
	assert_float_equal(m.torque(3, 0), -5, 0);
	assert_float_equal(m.torque(NAN, 0), 0, 0);
	assert_float_equal(m.torque(0, INFINITY), 0, 0);
	// Exit: no torque; enter again: the command is gone.
	assert_true(m.receive(to_motor(1, kExit), 0, 0, 0, &note).has_value());
	assert_false(m.enabled());
	assert_float_equal(m.torque(-1, 0), 0, 0);
	m.receive(to_motor(1, kEnter), 0, 0, 0, &note);
	assert_float_equal(m.torque(-1, 0), 0, 0);
	assert_true(note.empty());
}

void out_of_motor_mode(void **)
{
	MitMotor m(3);
	// A command is answered but drives nothing; entering clears it.
	std::optional<CanFrame> reply = m.receive(to_motor(3, kCommand), 0.5, -3, 0.25, nullptr);
	assert_true(reply.has_value());
	assert_false(m.enabled());
	assert_float_equal(m.torque(-1, 0), 0, 0);
	m.receive(to_motor(3, kEnter), 0.5, -3, 0.25, nullptr);
	assert_float_equal(m.torque(-1, 0), 0, 0);
	// The reply: the master's id 0, 6 bytes, the state as the motor sees it.
	assert_int_equal(reply->id, 0);
	assert_false(reply->extended || reply->rtr || reply->fd);
	assert_int_equal(reply->len, 6);
	const uint8_t expected[6] = { 0x03, 0x85, 0x1E, 0x78, 0x48, 0x65 };
	assert_memory_equal(reply->data, expected, 6);
	// Another reply id; over 11 bits, an extended frame.
	MitMotor a(4, MitRanges{}, 0x100), b(5, MitRanges{}, 0x12345);
	reply = a.receive(to_motor(4, kExit), 0, 0, 0, nullptr);
	assert_true(reply && reply->id == 0x100 && !reply->extended);
	reply = b.receive(to_motor(5, kExit), 0, 0, 0, nullptr);
	assert_true(reply && reply->id == 0x12345 && reply->extended);
}

void zeroing(void **)
{
	MitMotor m(1);
	// Zero at 3 rad: the reply already says 0 (0x7FFF, 32767 being just below).
	std::optional<CanFrame> reply = m.receive(to_motor(1, kZero), 3, 0, 0, nullptr);
	assert_true(reply.has_value());
	assert_int_equal(reply->data[1], 0x7F);
	assert_int_equal(reply->data[2], 0xFF);
	assert_false(m.enabled()); // FE changes no mode
	assert_float_equal(m.position(4), 1, 0);
	m.receive(to_motor(1, kEnter), 3, 0, 0, nullptr);
	m.receive(to_motor(1, kCommand), 3.9, 1.9, 0, nullptr);
	const double expected = kKp * (kPdes - 0.9) + kKd * (kVdes - 1.9) + kTff;
	assert_float_equal(m.torque(3.9, 1.9), expected, 1e-12);
	// The reported position saturates at the field's range.
	reply = m.receive(to_motor(1, kCommand), 3 + 20, 0, 0, nullptr);
	assert_int_equal(reply->data[1], 0xFF);
	assert_int_equal(reply->data[2], 0xFF);
	reply = m.receive(to_motor(1, kCommand), 3 - 20, 0, 0, nullptr);
	assert_int_equal(reply->data[1], 0x00);
	assert_int_equal(reply->data[2], 0x00);
}

void ignored_frames(void **)
{
	MitMotor m(1);
	std::string note;
	// Not its id: silently not for it.
	assert_false(m.receive(to_motor(2, kEnter), 0, 0, 0, &note).has_value());
	assert_true(note.empty());
	CanFrame f = to_motor(1, kEnter);
	f.len = 6;
	assert_false(m.receive(f, 0, 0, 0, &note).has_value());
	assert_string_equal(note.c_str(), "motor 1: a frame of 6 bytes, not 8: ignored");
	f = to_motor(1, kEnter);
	f.rtr = true;
	assert_false(m.receive(f, 0, 0, 0, &note).has_value());
	assert_string_equal(note.c_str(), "motor 1: a remote frame: ignored");
	f = to_motor(1, kEnter);
	f.extended = true;
	assert_false(m.receive(f, 0, 0, 0, &note).has_value());
	assert_string_equal(note.c_str(), "motor 1: an extended (29-bit) frame: ignored");
	f = to_motor(1, kEnter);
	f.fd = true;
	assert_false(m.receive(f, 0, 0, 0, nullptr).has_value());
	assert_false(m.enabled()); // none of them entered motor mode
	// FF ... FB is no special frame: a command like any other (all near the top).
	const uint8_t fb[8] = { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFB };
	assert_true(m.receive(to_motor(1, fb), 0, 0, 0, nullptr).has_value());
	assert_false(m.enabled());
	assert_int_equal(int(tcs::mit_special(fb)), int(tcs::MitSpecial::none));
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(known_bytes),       cmocka_unit_test(round_trips), cmocka_unit_test(torque_law),
		cmocka_unit_test(out_of_motor_mode), cmocka_unit_test(zeroing),     cmocka_unit_test(ignored_frames),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
