// Unit tests for the CAN bus in virtual time (wires/can/can_bus.h): frames
// back to back at their bit times, arbitration by identifier when the bus
// goes idle, per-source order, full queues. The frames' bit counts are the
// ones test_can_timing.cc works out by hand.
#include <cstdint>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "can_bus.h"
#include "can_test_frames.h"

namespace {

using tcs::CanBus;
using tcs::CanDelivery;
using tcs::CanFrame;

// 127 bits: id 0, eight zero bytes.
const CanFrame kZeros = can_test_frame(0x000, { 0, 0, 0, 0, 0, 0, 0, 0 });
// 79 bits: id 0x555, four 0xAA (no stuffing).
const CanFrame k555 = can_test_frame(0x555, { 0xAA, 0xAA, 0xAA, 0xAA });
// 126 bits: id 0x7FF, eight 0xFF.
const CanFrame k7FF = can_test_frame(0x7FF, { 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF });
// 53 bits: id 0, no data.
const CanFrame kEmpty = can_test_frame(0x000, {});

void hundred_frames(void **)
{
	CanBus bus(1000000, 0, 100);
	for (int i = 0; i < 100; i++)
		assert_true(bus.submit(1, i % 2 ? k555 : kZeros, 0));
	assert_int_equal(*bus.next_end(), 127000);
	std::vector<CanDelivery> d = bus.advance(INT64_MAX / 2);
	assert_int_equal(d.size(), 100);
	int64_t t = 0;
	for (int i = 0; i < 100; i++) {
		assert_int_equal(d[i].start_ns, t);
		t += i % 2 ? 79000 : 127000;
		assert_int_equal(d[i].end_ns, t);
		assert_int_equal(d[i].frame.id, i % 2 ? 0x555 : 0x000);
	}
	// 50 · 127 + 50 · 79 bits at 1000 ns each.
	assert_int_equal(d[99].end_ns, 10300000);
	assert_int_equal(bus.busy_ns(), 10300000);
	assert_false(bus.next_end().has_value());
}

void high_priority_overtakes(void **)
{
	CanBus bus(1000000, 0);
	assert_true(bus.submit(1, k555, 0));
	assert_true(bus.advance(0).empty()); // on the wire until 79 µs
	assert_int_equal(*bus.next_end(), 79000);
	assert_true(bus.submit(2, k7FF, 10000)); // low priority, queued
	assert_true(bus.advance(15000).empty());
	assert_true(bus.submit(3, kEmpty, 20000)); // high priority, later
	std::vector<CanDelivery> d = bus.advance(79000);
	assert_int_equal(d.size(), 1);
	assert_int_equal(d[0].source, 1);
	assert_int_equal(d[0].end_ns, 79000);
	// The bus went idle at 79 µs: id 0 won and is on the wire.
	assert_int_equal(*bus.next_end(), 79000 + 53000);
	d = bus.advance(1000000);
	assert_int_equal(d.size(), 2);
	assert_int_equal(d[0].source, 3);
	assert_int_equal(d[0].start_ns, 79000);
	assert_int_equal(d[0].end_ns, 132000);
	assert_int_equal(d[1].source, 2);
	assert_int_equal(d[1].start_ns, 132000);
	assert_int_equal(d[1].end_ns, 258000);
	assert_int_equal(bus.busy_ns(), 258000);
}

void idle_bus_waits_for_ready(void **)
{
	CanBus bus(500000, 0);
	assert_true(bus.submit(1, k7FF, 5000));
	assert_int_equal(*bus.next_end(), 5000 + 126 * 2000);
	assert_true(bus.advance(4999).empty());
	// Before it starts, a higher-priority frame ready earlier goes first.
	assert_true(bus.submit(2, kZeros, 3000));
	assert_true(bus.advance(4000).empty()); // time does not go back
	assert_true(bus.advance(4999).empty()); // it starts: on the wire
	std::vector<CanDelivery> d = bus.advance(600000);
	assert_int_equal(d.size(), 2);
	// Submitted after the bus was run to 4999: it starts no earlier.
	assert_int_equal(d[0].source, 2);
	assert_int_equal(d[0].start_ns, 4999);
	assert_int_equal(d[0].end_ns, 4999 + 127 * 2000);
	assert_int_equal(d[1].start_ns, 4999 + 127 * 2000);
	assert_int_equal(d[1].end_ns, 4999 + (127 + 126) * 2000);
	// Half way through a frame (106 µs), half of it counts as busy.
	assert_true(bus.submit(1, kEmpty, 1000000));
	assert_true(bus.advance(1000000 + 53000).empty());
	assert_int_equal(bus.busy_ns(), (127 + 126) * 2000 + 53000);
}

void same_source_in_order(void **)
{
	CanBus bus(1000000, 0);
	assert_true(bus.submit(1, can_test_frame(0x700, { 1 }), 0));
	assert_true(bus.submit(1, can_test_frame(0x100, { 2 }), 0));
	assert_true(bus.submit(2, can_test_frame(0x300, { 3 }), 0));
	std::vector<CanDelivery> d = bus.advance(1000000);
	assert_int_equal(d.size(), 3);
	// Source 1's 0x100 waits behind its 0x700, which loses to 0x300.
	assert_int_equal(d[0].frame.id, 0x300);
	assert_int_equal(d[1].frame.id, 0x700);
	assert_int_equal(d[2].frame.id, 0x100);
	assert_int_equal(d[1].start_ns, d[0].end_ns);
	assert_int_equal(d[2].start_ns, d[1].end_ns);
}

void full_queue_refuses(void **)
{
	CanBus bus(1000000, 0);
	for (int i = 0; i < 10; i++)
		assert_true(bus.submit(7, kZeros, 0));
	assert_false(bus.submit(7, kZeros, 0));
	assert_true(bus.submit(8, kZeros, 0)); // another source's queue
	assert_int_equal(bus.queued(7), 10);
	assert_true(bus.advance(0).empty()); // source 7's first is on the wire
	assert_int_equal(bus.queued(7), 9);
	assert_true(bus.submit(7, kZeros, 0));
	assert_false(bus.submit(7, kZeros, 0));
	CanBus none(1000000, 0, 0);
	assert_false(none.submit(1, kZeros, 0));
	assert_false(none.next_end().has_value());
}

void arbitration_order(void **)
{
	using tcs::can_arbitration_key;
	CanFrame data = can_test_frame(0x100, {});
	CanFrame remote = data;
	remote.rtr = true;
	CanFrame ext = can_test_frame(0x100 << 18, {}, true);
	CanFrame ext_remote = ext;
	ext_remote.rtr = true;
	CanFrame ext_lower_base = can_test_frame(0x0FF << 18 | 0x3FFFF, {}, true);
	CanFrame fd = data;
	fd.fd = true;
	CanFrame fd_remote = remote; // FD sends RRS dominant: no remote frame
	fd_remote.fd = true;
	assert_true(can_arbitration_key(data) < can_arbitration_key(remote));
	assert_true(can_arbitration_key(remote) < can_arbitration_key(ext)); // IDE
	assert_true(can_arbitration_key(ext) < can_arbitration_key(ext_remote));
	assert_true(can_arbitration_key(ext_lower_base) < can_arbitration_key(data));
	assert_true(can_arbitration_key(data) < can_arbitration_key(fd));
	assert_true(can_arbitration_key(fd) < can_arbitration_key(remote));
	assert_true(can_arbitration_key(fd_remote) == can_arbitration_key(fd));
	// On the bus: submitted worst first, delivered best first.
	CanBus bus(1000000, 0);
	const CanFrame order[] = { ext_lower_base, data, fd, remote, ext, ext_remote };
	for (int i = 5; i >= 0; i--)
		assert_true(bus.submit(uint32_t(i), order[i], 0));
	std::vector<CanDelivery> d = bus.advance(1000000);
	assert_int_equal(d.size(), 6);
	for (uint32_t i = 0; i < 6; i++)
		assert_int_equal(d[i].source, i);
	// The same field from two sources: the earlier ready, then the earlier submitted.
	assert_true(bus.submit(1, data, 2000000));
	assert_true(bus.submit(2, data, 1999999));
	assert_true(bus.submit(3, data, 1999999));
	d = bus.advance(3000000);
	assert_int_equal(d.size(), 3);
	assert_int_equal(d[0].source, 2);
	assert_int_equal(d[1].source, 3);
	assert_int_equal(d[2].source, 1);
}

} // namespace

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(hundred_frames),     cmocka_unit_test(high_priority_overtakes),
		cmocka_unit_test(idle_bus_waits_for_ready), cmocka_unit_test(same_source_in_order),
		cmocka_unit_test(full_queue_refuses), cmocka_unit_test(arbitration_order),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
