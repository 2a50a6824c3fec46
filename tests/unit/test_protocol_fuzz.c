/* Unit tests for tcs/protocol.h's tcs_msg_check() on what no preload
 * writes: random buffers of every length, and valid messages mutated;
 * whatever it accepts holds every range the coordinator relies on. */
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

/* ---- fuzz ------------------------------------------------------------------ */

/* What the coordinator relies on for every message tcs_msg_check() accepts. */
static void assert_invariants(const struct tcs_msg *m, const void *raw)
{
	assert_memory_equal(m, raw, sizeof *m);
	assert_int_equal(m->magic, TCS_PROTO_MAGIC);
	assert_int_equal(m->version, TCS_PROTO_VERSION);
	switch (m->type) {
	case TCS_MSG_HELLO:
		assert_true(m->arg > 0 && m->arg <= INT32_MAX);
		break;
	case TCS_MSG_BLOCK:
		assert_true(m->kind == TCS_BLOCK_SLEEP || m->kind == TCS_BLOCK_POLL || m->kind == TCS_BLOCK_SYNC ||
			    m->kind == TCS_BLOCK_SPIN);
		assert_int_equal(m->flags & ~TCS_BLOCK_FLAGS_ALL, 0);
		assert_true(m->slack >= 0);
		assert_true(m->deadline >= 0);
		assert_true(m->v >= 0);
		assert_true(m->cpu >= 0);
		break;
	case TCS_MSG_EARLY:
		assert_true(m->kind == TCS_EARLY_FD || m->kind == TCS_EARLY_SIGNAL);
		break;
	case TCS_MSG_DEV_OPEN:
		assert_true(m->arg >= 0 && m->arg < TCS_MAX_DEVICES);
		assert_int_equal(m->flags & ~TCS_DEV_FLAGS_ALL, 0);
		assert_true(m->flags & (TCS_DEV_READ | TCS_DEV_WRITE));
		break;
	case TCS_MSG_DEV_SYNC:
		assert_true(m->kind >= TCS_SYNC_READ && m->kind <= TCS_SYNC_POLL);
		assert_int_equal(m->flags & ~TCS_DEV_FLAGS_ALL, 0);
		assert_true(m->arg >= 0 && m->arg <= INT32_MAX && m->v >= 0 && m->cpu >= 0);
		break;
	case TCS_MSG_CHILD:
		assert_true(m->arg > 0 && m->arg <= INT32_MAX && m->v >= 0 && m->cpu >= 0);
		assert_int_equal(m->flags & ~(TCS_CHILD_V_KNOWN | TCS_CHILD_PARENT), 0);
		break;
	case TCS_MSG_TIMER:
		assert_true(m->flags < TCS_MAX_TIMERS);
		assert_true(m->kind >= 1 && m->kind <= 64);
		assert_true(m->deadline >= 0 && m->arg >= 0 && m->cpu >= 0);
		assert_true(m->v >= 0 && m->v <= INT32_MAX);
		break;
	case TCS_MSG_THREAD:
		assert_true(m->arg > 0 && m->arg <= INT32_MAX);
		break;
	case TCS_MSG_KILL:
		assert_true(m->arg >= -(int64_t)INT32_MAX && m->arg <= INT32_MAX && m->v >= 0 && m->cpu >= 0);
		break;
	case TCS_MSG_DOORBELL:
		break; /* only its type is read: look at the mailbox */
	default:
		print_error("accepted a message of type %u\n", m->type);
		fail();
	}
}

static void test_fuzz_random_buffers(void **state)
{
	uint64_t rng = 0x5eed5eed5eed5eedULL;
	unsigned char buf[64];
	unsigned long accepted = 0;
	for (int i = 0; i < 200000; i++) {
		for (size_t j = 0; j < sizeof buf; j += 8) {
			uint64_t r = test_rand(&rng);
			memcpy(buf + j, &r, 8);
		}
		long len = (long)(test_rand(&rng) % 65);
		/* Often give it the right header so the deeper checks get exercised. */
		uint64_t r = test_rand(&rng);
		if (r & 1) {
			uint32_t magic = TCS_PROTO_MAGIC;
			memcpy(buf, &magic, 4);
		}
		if (r & 2) {
			uint16_t version = TCS_PROTO_VERSION;
			memcpy(buf + 4, &version, 2);
		}
		if (r & 4) {
			uint16_t type = (uint16_t)(1 + (r >> 8) % 7);
			memcpy(buf + 6, &type, 2);
		}
		if (r & 8) {
			uint16_t kind = (uint16_t)((r >> 16) % 4);
			memcpy(buf + 12, &kind, 2);
		}
		if (r & 16) {
			uint16_t flags = (uint16_t)((r >> 24) % 5);
			memcpy(buf + 14, &flags, 2);
		}
		if (r & 32) { /* clear the sign bits of deadline, v, cpu, arg, slack (little- or big-endian) */
			for (int f = 0; f < 5; f++)
				buf[16 + 8 * f + (__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__ ? 7 : 0)] &= 0x7f;
		}
		if (r & 64) {
			int64_t arg = (int64_t)((r >> 32) % 70000) - 100;
			memcpy(buf + 40, &arg, 8);
		}
		if (r & 128)
			len = 56;

		struct tcs_msg out;
		const char *why = tcs_msg_check(buf, len, &out);
		if (why == NULL) {
			assert_int_equal(len, 56);
			assert_invariants(&out, buf);
			accepted++;
		} else {
			assert_true(why[0] != '\0');
		}
	}
	print_message("      %lu of 200000 random buffers accepted\n", accepted);
	/* The loop must have reached the deeper checks, or it tested little. */
	assert_true(accepted > 100);
}

static void test_fuzz_mutations(void **state)
{
	uint64_t rng = 0xfeedfacecafebeefULL;
	struct tcs_msg (*const makers[])(void) = { valid_hello, valid_block, valid_early };
	unsigned long accepted = 0, rejected = 0;
	for (int i = 0; i < 300000; i++) {
		struct tcs_msg m = makers[i % 3]();
		unsigned char raw[56];
		memcpy(raw, &m, sizeof raw);
		uint64_t r = test_rand(&rng);
		switch (r % 4) {
		case 0: /* flip one bit */
			raw[(r >> 8) % 56] ^= (unsigned char)(1u << ((r >> 16) % 8));
			break;
		case 1: /* replace one byte */
			raw[(r >> 8) % 56] = (unsigned char)(r >> 16);
			break;
		case 2: { /* replace one field with a random or edge value */
			static const size_t offs[] = { 0, 4, 6, 8, 12, 14, 16, 24, 32, 40, 48 };
			static const size_t sizes[] = { 4, 2, 2, 4, 2, 2, 8, 8, 8, 8 };
			size_t f = (r >> 8) % 10;
			uint64_t v = test_rand(&rng);
			static const uint64_t edges[] = { 0, 1, 2, 3, 4, 5, UINT64_MAX, (uint64_t)INT64_MIN,
							  (uint64_t)INT64_MAX, (uint64_t)INT32_MAX,
							  (uint64_t)INT32_MAX + 1 };
			if ((r >> 16) & 1)
				v = edges[(r >> 17) % (sizeof edges / sizeof edges[0])];
			memcpy(raw + offs[f], &v, sizes[f]); /* little-endian: the low bytes */
			break;
		}
		default: /* several random bytes */
			for (int k = 0; k < 4; k++)
				raw[test_rand(&rng) % 56] = (unsigned char)test_rand(&rng);
			break;
		}
		struct tcs_msg out;
		const char *why = tcs_msg_check(raw, 56, &out);
		if (why == NULL) {
			assert_invariants(&out, raw);
			accepted++;
		} else {
			assert_true(why[0] != '\0');
			rejected++;
		}
	}
	print_message("      mutations: %lu accepted, %lu rejected\n", accepted, rejected);
	assert_true(accepted > 1000);
	assert_true(rejected > 1000);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_fuzz_random_buffers),
		cmocka_unit_test(test_fuzz_mutations),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
