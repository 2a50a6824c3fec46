/* What the tests of tcs/protocol.h share: valid messages of three types,
 * and checks of tcs_msg_check()'s verdict on a message received whole.
 * Include after <cmocka.h>. */
#ifndef TCS_PROTOCOL_CHECKS_H
#define TCS_PROTOCOL_CHECKS_H

#include <string.h>

#include <tcs/protocol.h>

static inline struct tcs_msg valid_hello(void)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_HELLO, 0);
	m.arg = 4242;
	return m;
}

static inline struct tcs_msg valid_block(void)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_BLOCK, 17);
	m.kind = TCS_BLOCK_POLL;
	m.flags = TCS_BLOCK_ABSOLUTE | TCS_BLOCK_RECHECK;
	m.deadline = 5000000000LL;
	m.v = 4000000000LL;
	m.cpu = 123456789;
	return m;
}

static inline struct tcs_msg valid_early(void)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_EARLY, 17);
	m.kind = TCS_EARLY_SIGNAL;
	return m;
}

/* Checks m as received (exactly 56 bytes) and returns the verdict. */
static inline const char *check(struct tcs_msg m, struct tcs_msg *out)
{
	struct tcs_msg scratch;
	return tcs_msg_check(&m, (long)sizeof m, out ? out : &scratch);
}

static inline void assert_accepted(struct tcs_msg m)
{
	struct tcs_msg out;
	memset(&out, 0xa5, sizeof out);
	const char *why = check(m, &out);
	if (why) {
		print_error("rejected: %s\n", why);
		fail();
	}
	assert_memory_equal(&out, &m, sizeof m);
}

static inline void assert_rejected(struct tcs_msg m)
{
	const char *why = check(m, NULL);
	assert_non_null(why);
	assert_true(why[0] != '\0');
}

#endif
