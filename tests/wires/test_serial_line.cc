// SerialDirection and the frame's bits (wires/serial/serial_line.h): when
// bytes arrive, worked out by hand from bits / baud.
#include <termios.h>

#include <cstdint>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "serial_line.h"

namespace {

using tcs::SerialDirection;

void frame_bits_from_settings(void **)
{
	assert_int_equal(*tcs::serial_frame_bits(8, false, 1), 10);
	assert_int_equal(*tcs::serial_frame_bits(7, true, 2), 11);
	assert_int_equal(*tcs::serial_frame_bits(5, false, 1), 7);
	assert_false(tcs::serial_frame_bits(9, false, 1).ok());
	assert_false(tcs::serial_frame_bits(4, false, 1).ok());
	assert_false(tcs::serial_frame_bits(8, false, 3).ok());
}

void frame_bits_from_cflag(void **)
{
	assert_int_equal(tcs::serial_frame_bits_cflag(CS8), 10);
	assert_int_equal(tcs::serial_frame_bits_cflag(CS8 | CSTOPB), 11);
	assert_int_equal(tcs::serial_frame_bits_cflag(CS7 | PARENB), 10);
	assert_int_equal(tcs::serial_frame_bits_cflag(CS8 | PARENB | CSTOPB), 12);
	assert_int_equal(tcs::serial_frame_bits_cflag(CS5), 7);
	assert_int_equal(tcs::serial_frame_bits_cflag(CS6 | CREAD | CLOCAL), 8);
}

void ten_bytes_at_57600(void **)
{
	SerialDirection line(57600, 10);
	// 100 bits at 57600 baud: 1736111.1 ns.
	assert_int_equal(line.send(10, 0), 1736111);
	assert_int_equal(line.pending(), 10);
	assert_int_equal(line.arrival(0), 173611);  // 1e10 / 57600
	assert_int_equal(line.arrival(8), 1562500); // 9e10 / 57600, exactly
	assert_int_equal(line.idle_at(), 1736111);
}

void byte_times_do_not_drift(void **)
{
	// At 115200 a byte is 86805.56 ns: 1000 bytes written one at a time
	// end at floor(1000e10 / 115200), not at 1000 * 86805.
	SerialDirection line(115200, 10);
	int64_t end = 0;
	for (int i = 0; i < 1000; i++)
		end = line.send(1, 0);
	assert_int_equal(end, 86805555);
	// Each write ready just as the previous one has left: the same.
	SerialDirection again(115200, 10);
	int64_t t = 0;
	for (int i = 0; i < 1000; i++)
		t = again.send(1, t);
	assert_int_equal(t, 86805555);
}

void take_hands_over_what_has_arrived(void **)
{
	SerialDirection line(57600, 10);
	line.send(10, 0);
	assert_int_equal(line.take(173610), 0);
	assert_int_equal(line.take(173611), 1);
	// Byte 9 ends at 1736111: not yet at 1736110.
	assert_int_equal(line.take(1736110), 8);
	assert_int_equal(line.pending(), 1);
	assert_int_equal(line.arrival(0), 1736111);
	assert_int_equal(line.take(2000000), 1);
	assert_int_equal(line.pending(), 0);
	assert_int_equal(line.take(3000000), 0);
}

void a_write_waits_for_the_wire(void **)
{
	SerialDirection line(57600, 10);
	line.send(10, 0);
	// Ready at 1 us, but behind 10 bytes: the 11th byte, 11e10 / 57600.
	assert_int_equal(line.send(1, 1000), 1909722);
	// After a quiet gap, a new run from its ready time.
	assert_int_equal(line.send(2, 10000000), 10347222);
	assert_int_equal(line.arrival(11), 10173611);
	assert_int_equal(line.take(20000000), 13);
}

void a_new_baud_for_later_bytes(void **)
{
	SerialDirection line(57600, 10);
	assert_int_equal(line.send(1, 0), 173611);
	line.set_baud(115200, 10);
	// Behind the first byte, at 86805 ns a byte.
	assert_int_equal(line.send(1, 0), 173611 + 86805);
	line.set_baud(9600, 11);
	// 11 bits at 9600: 1145833 ns, from an idle wire at 1 s.
	assert_int_equal(line.send(1, 1000000000), 1001145833);
}

void discard_drops_what_has_not_arrived(void **)
{
	SerialDirection line(57600, 10);
	line.send(10, 0);
	// Bytes 0 and 1 arrived by 500 us (173611, 347222); byte 2 at 520833.
	assert_int_equal(line.discard(500000), 8);
	assert_int_equal(line.pending(), 2);
	assert_int_equal(line.idle_at(), 500000);
	assert_int_equal(line.send(1, 0), 500000 + 173611);
	assert_int_equal(line.take(10000000), 3);
	assert_int_equal(line.discard(20000000), 0);
}

void nothing_sent(void **)
{
	SerialDirection line(57600, 10);
	assert_int_equal(line.send(0, 5), 5);
	assert_int_equal(line.pending(), 0);
	line.send(1, 0);
	assert_int_equal(line.send(0, 5), 173611);
	assert_true(line.arrival(1) == INT64_MAX);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(frame_bits_from_settings),
		cmocka_unit_test(frame_bits_from_cflag),
		cmocka_unit_test(ten_bytes_at_57600),
		cmocka_unit_test(byte_times_do_not_drift),
		cmocka_unit_test(take_hands_over_what_has_arrived),
		cmocka_unit_test(a_write_waits_for_the_wire),
		cmocka_unit_test(a_new_baud_for_later_bytes),
		cmocka_unit_test(discard_drops_what_has_not_arrived),
		cmocka_unit_test(nothing_sent),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
