/* Unit tests for tcs/protocol.h: the wire format and tcs_msg_check(), the
 * coordinator's only defence against whatever a controller sends: every
 * message it accepts, and every way one is refused. Random and mutated
 * messages are test_protocol_fuzz.c's. */
#include <limits.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <tcs/protocol.h>
#include <tcs/vtime.h>

#include "protocol_checks.h"
#include "test_i64.h"

/* The wire layout is fixed: both sides are built separately and the preload
 * may be an older build than the coordinator. */
_Static_assert(sizeof(struct tcs_msg) == 56, "tcs_msg is 56 bytes on the wire");
_Static_assert(offsetof(struct tcs_msg, magic) == 0, "layout");
_Static_assert(offsetof(struct tcs_msg, version) == 4, "layout");
_Static_assert(offsetof(struct tcs_msg, type) == 6, "layout");
_Static_assert(offsetof(struct tcs_msg, seq) == 8, "layout");
_Static_assert(offsetof(struct tcs_msg, kind) == 12, "layout");
_Static_assert(offsetof(struct tcs_msg, flags) == 14, "layout");
_Static_assert(offsetof(struct tcs_msg, deadline) == 16, "layout");
_Static_assert(offsetof(struct tcs_msg, v) == 24, "layout");
_Static_assert(offsetof(struct tcs_msg, cpu) == 32, "layout");
_Static_assert(offsetof(struct tcs_msg, arg) == 40, "layout");
_Static_assert(offsetof(struct tcs_msg, slack) == 48, "layout");

/* ---- layout ---------------------------------------------------------------- */

static void test_msg_make(void **state)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_WAKE, 0xdeadbeefu);
	assert_int_equal(sizeof m, 56);
	assert_int_equal(m.magic, TCS_PROTO_MAGIC);
	assert_int_equal(m.version, TCS_PROTO_VERSION);
	assert_int_equal(m.type, TCS_MSG_WAKE);
	assert_int_equal(m.seq, 0xdeadbeefu);
	assert_int_equal(m.kind, 0);
	assert_int_equal(m.flags, 0);
	assert_i64_eq(m.deadline, 0);
	assert_i64_eq(m.v, 0);
	assert_i64_eq(m.cpu, 0);
	assert_i64_eq(m.arg, 0);
	/* The magic reads "tcs1" in memory on a little-endian machine. */
	unsigned char raw[56];
	memcpy(raw, &m, sizeof raw);
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
	assert_memory_equal(raw, "tcs1", 4);
#endif
}

/* ---- accepted -------------------------------------------------------------- */

static void test_valid_hello(void **state)
{
	assert_accepted(valid_hello());
	struct tcs_msg m = valid_hello();
	m.arg = 1;
	assert_accepted(m);
	m.arg = INT32_MAX;
	assert_accepted(m);
}

static void test_valid_block(void **state)
{
	assert_accepted(valid_block());
	struct tcs_msg m = valid_block();
	m.kind = TCS_BLOCK_SLEEP;
	for (uint16_t f = 0; f <= TCS_BLOCK_FLAGS_ALL; f++) {
		m.flags = f;
		assert_accepted(m);
	}
	m.flags = 0;
	m.deadline = TCS_NEVER; /* an infinite wait */
	assert_accepted(m);
	m.deadline = 0;
	m.v = 0;
	m.cpu = 0;
	assert_accepted(m);
	m.v = INT64_MAX;
	m.cpu = INT64_MAX;
	assert_accepted(m);
	m.seq = UINT32_MAX;
	assert_accepted(m);
	m.kind = TCS_BLOCK_SYNC; /* a thread waiting for another */
	assert_accepted(m);
	m.slack = INT64_MAX; /* the coordinator bounds what it takes of it */
	assert_accepted(m);
	m.slack = -1; /* a timer slack is never negative */
	assert_rejected(m);
}

/* A thread hands over its own channel: the tid must be one. */
static void test_thread_message(void **state)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_THREAD, 0);
	m.arg = 4242;
	assert_accepted(m);
	static const int64_t bad[] = { 0, -1, (int64_t)INT32_MAX + 1, INT64_MIN };
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		m.arg = bad[i];
		assert_rejected(m);
	}
}

/* A signal sent to kill()'s pid argument: any process, group or all. */
/* A DOORBELL says only "look at my mailbox": any fields will do. */
static void test_doorbell_message(void **state)
{
	(void)state;
	struct tcs_msg m = tcs_msg_make(TCS_MSG_DOORBELL, 9);
	assert_accepted(m);
	m.arg = INT64_MIN;
	m.deadline = -1;
	assert_accepted(m);
}

static void test_kill_message(void **state)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_KILL, 3);
	static const int64_t good[] = { 4242, 0, -1, -4242, INT32_MAX, -(int64_t)INT32_MAX };
	for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
		m.arg = good[i];
		assert_accepted(m);
	}
	static const int64_t bad[] = { (int64_t)INT32_MAX + 1, INT32_MIN, INT64_MIN, INT64_MAX };
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		m.arg = bad[i];
		assert_rejected(m);
	}
	m.arg = 1;
	m.v = -1;
	assert_rejected(m);
	m.v = 0;
	m.cpu = -1;
	assert_rejected(m);
}

static void test_valid_early(void **state)
{
	assert_accepted(valid_early());
	struct tcs_msg m = valid_early();
	m.kind = TCS_EARLY_FD;
	assert_accepted(m);
	m.seq = 0;
	assert_accepted(m);
}

/* The message need not be aligned in the receive buffer. */
static void test_unaligned_buffer(void **state)
{
	unsigned char buf[64];
	struct tcs_msg m = valid_block(), out;
	for (size_t off = 0; off < 8; off++) {
		memset(buf, 0, sizeof buf);
		memcpy(buf + off, &m, sizeof m);
		memset(&out, 0, sizeof out);
		assert_null(tcs_msg_check(buf + off, 56, &out));
		assert_memory_equal(&out, &m, sizeof m);
	}
}

/* ---- rejected -------------------------------------------------------------- */

static void test_wrong_size(void **state)
{
	unsigned char buf[128];
	struct tcs_msg m = valid_hello(), out;
	memset(buf, 0, sizeof buf);
	memcpy(buf, &m, sizeof m);
	static const long lens[] = { 0, 1, 4, 48, 55, 57, 64, 96, 128, LONG_MAX, 56L + (1L << 32) };
	for (size_t i = 0; i < sizeof lens / sizeof lens[0]; i++) {
		memset(&out, 0x5a, sizeof out);
		const char *why = tcs_msg_check(buf, lens[i], &out);
		assert_non_null(why);
		assert_string_equal(why, "wrong size");
	}
	/* A failed receive is reported as such, not as a bad message. */
	static const long negative[] = { -1, -56, -4, LONG_MIN };
	for (size_t i = 0; i < sizeof negative / sizeof negative[0]; i++) {
		const char *why = tcs_msg_check(buf, negative[i], &out);
		assert_non_null(why);
		assert_string_not_equal(why, "wrong size");
	}
	assert_null(tcs_msg_check(buf, 56, &out));
}

static void test_bad_magic(void **state)
{
	struct tcs_msg m = valid_block();
	m.magic = 0;
	assert_rejected(m);
	m.magic = TCS_PROTO_MAGIC ^ 1u;
	assert_rejected(m);
	m.magic = 0x70736374u; /* the clock page's magic */
	assert_rejected(m);
	m.magic = __builtin_bswap32(TCS_PROTO_MAGIC);
	assert_rejected(m);
}

static void test_wrong_version(void **state)
{
	static const uint16_t versions[] = { 0, TCS_PROTO_VERSION + 1, 0xffff, 0x100 };
	for (size_t i = 0; i < sizeof versions / sizeof versions[0]; i++) {
		struct tcs_msg m = valid_hello();
		m.version = versions[i];
		assert_rejected(m);
		m = valid_block();
		m.version = versions[i];
		assert_rejected(m);
	}
}

static void test_unknown_type(void **state)
{
	static const uint16_t types[] = { 0, 12, 13, 100, 0xffff, 0x0101 };
	for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
		struct tcs_msg m = valid_block();
		m.type = types[i];
		assert_rejected(m);
	}
}

static void test_device_messages(void **state)
{
	struct tcs_msg out, m = tcs_msg_make(TCS_MSG_DEV_OPEN, 3);
	m.arg = 2;
	m.flags = TCS_DEV_READ | TCS_DEV_NONBLOCK;
	assert_null(tcs_msg_check(&m, sizeof m, &out));
	m.arg = TCS_MAX_DEVICES;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out)); /* no such device */
	m.arg = -1;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));
	m.arg = 0;
	m.flags = TCS_DEV_NONBLOCK; /* neither read nor write */
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));
	m.flags = 0x80;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));

	m = tcs_msg_make(TCS_MSG_DEV_SYNC, 4);
	m.kind = TCS_SYNC_WRITE;
	m.arg = 1;
	m.v = 5;
	m.cpu = 7;
	assert_null(tcs_msg_check(&m, sizeof m, &out));
	assert_int_equal(out.kind, TCS_SYNC_WRITE);
	m.kind = 0;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));
	m.kind = TCS_SYNC_DRAIN; /* (a wire's tcdrain) */
	assert_null(tcs_msg_check(&m, sizeof m, &out));
	m.kind = 5;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));
	m.kind = TCS_SYNC_READ;
	m.flags = TCS_DEV_DEADLINE; /* a wire's read with a deadline: never a negative one */
	m.deadline = -1;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));
	m.deadline = 9;
	assert_null(tcs_msg_check(&m, sizeof m, &out));
	m.flags = 0;
	m.arg = -3;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));
	m.arg = 1;
	m.v = -1;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));
	m.v = 0;
	m.flags = 0x40;
	assert_non_null(tcs_msg_check(&m, sizeof m, &out));
}

static void test_wake_to_coordinator(void **state)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_WAKE, 1);
	m.kind = TCS_WAKE_DEADLINE;
	m.v = 1000;
	assert_rejected(m);
	m.kind = TCS_WAKE_EARLY;
	assert_rejected(m);
}

static void test_block_bad_kind(void **state)
{
	static const uint16_t kinds[] = { 0, 5, 6, 0xffff, 0x0101 };
	for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++) {
		struct tcs_msg m = valid_block();
		m.kind = kinds[i];
		assert_rejected(m);
	}
}

static void test_block_bad_flags(void **state)
{
	for (unsigned bit = 0; bit < 16; bit++) {
		if (TCS_BLOCK_FLAGS_ALL & (1u << bit))
			continue; /* a known flag */
		struct tcs_msg m = valid_block();
		m.flags = (uint16_t)(1u << bit);
		assert_rejected(m);
		m.flags = (uint16_t)(TCS_BLOCK_FLAGS_ALL | (1u << bit));
		assert_rejected(m);
	}
	struct tcs_msg m = valid_block();
	m.flags = 0xffff;
	assert_rejected(m);
}

static void test_block_negative_times(void **state)
{
	static const int64_t neg[] = { -1, -1000000000LL, INT64_MIN };
	for (size_t i = 0; i < sizeof neg / sizeof neg[0]; i++) {
		struct tcs_msg m = valid_block();
		m.deadline = neg[i];
		assert_rejected(m);
		m = valid_block();
		m.v = neg[i];
		assert_rejected(m);
		m = valid_block();
		m.cpu = neg[i];
		assert_rejected(m);
	}
}

static void test_early_bad_reason(void **state)
{
	static const uint16_t kinds[] = { 0, 3, 4, 0xffff };
	for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++) {
		struct tcs_msg m = valid_early();
		m.kind = kinds[i];
		assert_rejected(m);
	}
}

static void test_hello_bad_pid(void **state)
{
	static const int64_t pids[] = { 0, -1, INT32_MIN, (int64_t)INT32_MAX + 1, UINT32_MAX, INT64_MAX, INT64_MIN };
	for (size_t i = 0; i < sizeof pids / sizeof pids[0]; i++) {
		struct tcs_msg m = valid_hello();
		m.arg = pids[i];
		assert_rejected(m);
	}
}

static void test_timer_messages(void **state)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_TIMER, 9);
	m.flags = 0; /* ITIMER_REAL */
	m.kind = 14; /* SIGALRM */
	m.deadline = 1000000;
	m.arg = 1000000;
	m.v = 0;
	assert_accepted(m);
	m.deadline = TCS_NEVER; /* disarm */
	m.v = 4242;            /* a thread */
	m.flags = TCS_MAX_TIMERS - 1;
	assert_accepted(m);
	struct tcs_msg bad[] = { m, m, m, m, m, m, m };
	bad[0].flags = TCS_MAX_TIMERS;
	bad[1].kind = 0;
	bad[2].kind = 65;
	bad[3].deadline = -1;
	bad[4].arg = -5;
	bad[5].v = (int64_t)INT32_MAX + 1;
	bad[6].cpu = -1;
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		assert_rejected(bad[i]);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_msg_make),
		cmocka_unit_test(test_valid_hello),
		cmocka_unit_test(test_valid_block),
		cmocka_unit_test(test_thread_message),
		cmocka_unit_test(test_doorbell_message),
		cmocka_unit_test(test_kill_message),
		cmocka_unit_test(test_valid_early),
		cmocka_unit_test(test_unaligned_buffer),
		cmocka_unit_test(test_wrong_size),
		cmocka_unit_test(test_bad_magic),
		cmocka_unit_test(test_wrong_version),
		cmocka_unit_test(test_unknown_type),
		cmocka_unit_test(test_device_messages),
		cmocka_unit_test(test_wake_to_coordinator),
		cmocka_unit_test(test_block_bad_kind),
		cmocka_unit_test(test_block_bad_flags),
		cmocka_unit_test(test_block_negative_times),
		cmocka_unit_test(test_early_bad_reason),
		cmocka_unit_test(test_hello_bad_pid),
		cmocka_unit_test(test_timer_messages),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
