// Unit tests for frames of signals (wires/can/can_signals.h): layouts and
// their refusals, values packed with scale, offset, byte order and
// saturation into bytes worked out by hand, and read back.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "can_signals.h"

namespace {

using tcs::CanByteOrder;
using tcs::CanField;
using tcs::CanFrame;
using tcs::CanLayout;
using tcs::CanType;

CanField field(const char *name, CanType type, double scale = 1, double offset = 0,
	       CanByteOrder order = CanByteOrder::little, int start = -1)
{
	CanField f;
	f.name = name;
	f.type = type;
	f.scale = scale;
	f.offset = offset;
	f.order = order;
	f.start = start;
	return f;
}

// angle int16 LE ·0.01 (0-1), mode uint8 (2), speed int32 BE ·0.5 - 100
// (3-6), flag int8 at byte 7.
CanLayout drive_layout()
{
	tcs::Result<CanLayout> l = tcs::can_layout({ field("angle", CanType::int16, 0.01),
						     field("mode", CanType::uint8),
						     field("speed", CanType::int32, 0.5, -100, CanByteOrder::big),
						     field("flag", CanType::int8, 1, 0, CanByteOrder::little, 7) },
						   false);
	assert_true(l.ok());
	return *l;
}

void pack_and_unpack(void **)
{
	const CanLayout l = drive_layout();
	assert_int_equal(l.end, 8);
	assert_int_equal(l.len, 8);
	assert_int_equal(l.fields[2].start, 3);
	CanFrame f;
	f.id = 0x321;
	f.data[20] = 9;
	// 1.234/0.01 → 123 = 0x007B; 300 saturates to 255; (50 + 100)/0.5 = 300
	// = 0x0000012C, big-endian; -1.6 rounds to -2 = 0xFE.
	const double values[] = { 1.234, 300, 50, -1.6 };
	tcs::can_pack(l, values, f);
	assert_int_equal(f.id, 0x321);
	assert_int_equal(f.len, 8);
	assert_false(f.fd);
	const uint8_t bytes[8] = { 0x7B, 0x00, 0xFF, 0x00, 0x00, 0x01, 0x2C, 0xFE };
	assert_memory_equal(f.data, bytes, 8);
	assert_int_equal(f.data[20], 0); // the rest is cleared
	std::vector<double> back;
	std::string why;
	assert_true(tcs::can_unpack(l, f, back, &why));
	assert_int_equal(back.size(), 4);
	assert_float_equal(back[0], 1.23, 1e-12);
	assert_float_equal(back[1], 255, 0);
	assert_float_equal(back[2], 50, 0);
	assert_float_equal(back[3], -2, 0);
}

void saturation(void **)
{
	const CanLayout l = drive_layout();
	CanFrame f;
	// -400/0.01 = -40000 → -32768 = 0x8000; NaN → 0; -1e12 → INT32_MIN; 1000 → 127.
	const double values[] = { -400, NAN, -1e12, 1000 };
	tcs::can_pack(l, values, f);
	const uint8_t bytes[8] = { 0x00, 0x80, 0x00, 0x80, 0x00, 0x00, 0x00, 0x7F };
	assert_memory_equal(f.data, bytes, 8);
	tcs::Result<CanLayout> u = tcs::can_layout({ field("big", CanType::uint32), field("small", CanType::uint16),
						     field("neg", CanType::uint8) },
						   false);
	assert_true(u.ok());
	// 4294967295.4 rounds to the top; 65535.5 rounds up, past it; -3 → 0.
	const double uvalues[] = { 4294967295.4, 65535.5, -3 };
	tcs::can_pack(*u, uvalues, f);
	assert_int_equal(f.len, 7);
	const uint8_t ubytes[7] = { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x00 };
	assert_memory_equal(f.data, ubytes, 7);
	std::vector<double> back;
	assert_true(tcs::can_unpack(*u, f, back, nullptr));
	assert_float_equal(back[0], 4294967295.0, 0);
	assert_float_equal(back[1], 65535, 0);
}

void floats(void **)
{
	tcs::Result<CanLayout> l = tcs::can_layout(
		{ field("x", CanType::float32, 2, 1, CanByteOrder::big), field("y", CanType::float32) }, false);
	assert_true(l.ok());
	CanFrame f;
	// (7 - 1)/2 = 3.0f = 0x40400000; -0.5f = 0xBF000000, little-endian.
	const double values[] = { 7, -0.5 };
	tcs::can_pack(*l, values, f);
	const uint8_t bytes[8] = { 0x40, 0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0xBF };
	assert_memory_equal(f.data, bytes, 8);
	std::vector<double> back;
	assert_true(tcs::can_unpack(*l, f, back, nullptr));
	assert_float_equal(back[0], 7, 0);
	assert_float_equal(back[1], -0.5, 0);
	// A finite value past a float's range saturates; NaN and inf are kept.
	const double wide[] = { 1e300, INFINITY };
	tcs::can_pack(*l, wide, f);
	assert_true(tcs::can_unpack(*l, f, back, nullptr));
	assert_float_equal(back[0], 2.0 * 3.4028234663852886e38 + 1, 1e25);
	assert_true(std::isinf(back[1]) && back[1] > 0);
	const double nan[] = { NAN, NAN };
	tcs::can_pack(*l, nan, f);
	assert_true(tcs::can_unpack(*l, f, back, nullptr));
	assert_true(std::isnan(back[0]) && std::isnan(back[1]));
}

void refused_layouts(void **)
{
	tcs::Result<CanLayout> l =
		tcs::can_layout({ field("a", CanType::uint16, 1, 0, CanByteOrder::little, 0),
				  field("b", CanType::uint8, 1, 0, CanByteOrder::little, 1) },
				false);
	assert_false(l.ok());
	assert_string_equal(l.error().message.c_str(), "field 'b' (byte 1) overlaps field 'a' (bytes 0..1)");
	l = tcs::can_layout({ field("a", CanType::int32), field("b", CanType::int32), field("c", CanType::uint8) },
			    false);
	assert_false(l.ok());
	assert_string_equal(l.error().message.c_str(), "field 'c' (byte 8) ends past the frame's 8 bytes");
	l = tcs::can_layout({ field("far", CanType::int16, 1, 0, CanByteOrder::little, 1 << 30) }, true);
	assert_false(l.ok());
	assert_true(l.error().message.find("'far'") != std::string::npos);
	l = tcs::can_layout({ field("s", CanType::int16, 0) }, false);
	assert_false(l.ok());
	assert_string_equal(l.error().message.c_str(), "field 's': scale must be finite and not 0, offset finite");
	assert_false(tcs::can_layout({ field("s", CanType::int16, 1, NAN) }, false).ok());
	l = tcs::can_layout({ field("neg", CanType::int16, 1, 0, CanByteOrder::little, -2) }, false);
	assert_false(l.ok());
	assert_string_equal(l.error().message.c_str(), "field 'neg': start byte -2 is before 0");
	// FD: 64 bytes hold 16 int32s, not 17.
	std::vector<CanField> many(16, field("v", CanType::int32));
	assert_true(tcs::can_layout(many, true).ok());
	many.push_back(field("w", CanType::int32));
	assert_false(tcs::can_layout(many, true).ok());
}

void fd_and_short_frames(void **)
{
	// Fields up to byte 10: an FD frame of 12 bytes.
	tcs::Result<CanLayout> l =
		tcs::can_layout({ field("a", CanType::uint16, 1, 0, CanByteOrder::big, 8) }, true);
	assert_true(l.ok());
	assert_int_equal(l->end, 10);
	assert_int_equal(l->len, 12);
	CanFrame f;
	const double v[] = { 0x1234 };
	tcs::can_pack(*l, v, f);
	assert_true(f.fd);
	assert_int_equal(f.len, 12);
	assert_int_equal(f.data[8], 0x12);
	assert_int_equal(f.data[9], 0x34);
	// A frame shorter than the signals need is refused, values untouched.
	const CanLayout d = drive_layout();
	f.fd = false;
	f.len = 6;
	std::vector<double> values = { 42 };
	std::string why;
	assert_false(tcs::can_unpack(d, f, values, &why));
	assert_string_equal(why.c_str(), "a frame of 6 bytes: its signals need 8");
	assert_int_equal(values.size(), 1);
	assert_float_equal(values[0], 42, 0);
	// No fields: an empty frame.
	l = tcs::can_layout({}, false);
	assert_true(l.ok() && l->len == 0);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(pack_and_unpack), cmocka_unit_test(saturation),
		cmocka_unit_test(floats),          cmocka_unit_test(refused_layouts),
		cmocka_unit_test(fd_and_short_frames),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
