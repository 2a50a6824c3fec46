/* Unit tests for the preload's fd table (libtcs_preload/fd_table.c): an
 * entry read back whole, and closing, duplicating and forking done once
 * for every kind, through the operations its entry names. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "fd_table.h"

/* What the operations of the two test kinds were asked. */
static struct {
	int forgets, copies, after_forks;
	int last_fd;
	struct tcs_fd last;
} seen;

static void note(int fd, const struct tcs_fd *e)
{
	seen.last_fd = fd;
	seen.last = *e;
}

static void kind_forget(int fd, const struct tcs_fd *e)
{
	seen.forgets++;
	note(fd, e);
}

static void kind_copy(int to, const struct tcs_fd *e)
{
	seen.copies++;
	note(to, e);
}

static void kind_after_fork(int fd, const struct tcs_fd *e)
{
	seen.after_forks++;
	note(fd, e);
}

static const struct tcs_fd_ops served_ops = {
	.kind = TCS_FD_SERIAL, .served = 1, .forget = kind_forget, .copy = kind_copy, .after_fork = kind_after_fork,
};
static const struct tcs_fd_ops plain_ops = { .kind = TCS_FD_RANDOM };

static int reset(void **state)
{
	(void)state;
	tcs_fd_forget_range(0, TCS_FD_MAX);
	memset(&seen, 0, sizeof seen);
	return 0;
}

static void set(int fd, const struct tcs_fd_ops *ops, int handle, unsigned dev, unsigned slot, unsigned flags)
{
	struct tcs_fd e = { ops, handle, dev, slot, flags };
	tcs_fd_set(fd, &e);
}

static void test_an_fd_not_set_is_not_tcs_s(void **state)
{
	(void)state;
	struct tcs_fd e;
	assert_false(tcs_fd_of(3, &e));
	assert_false(tcs_fd_of(-1, &e));
	assert_false(tcs_fd_of(TCS_FD_MAX, &e));
	set(TCS_FD_MAX, &plain_ops, 1, 0, 0, 0); /* beyond the table: nothing */
	assert_false(tcs_fd_of(TCS_FD_MAX, &e));
}

static void test_an_entry_reads_back_whole(void **state)
{
	(void)state;
	struct tcs_fd e;
	set(7, &served_ops, -1, 255, 63, 0x81);
	assert_true(tcs_fd_of(7, &e));
	assert_ptr_equal(e.ops, &served_ops);
	assert_int_equal(e.handle, -1);
	assert_int_equal(e.dev, 255);
	assert_int_equal(e.slot, 63);
	assert_int_equal(e.flags, 0x81);
	set(TCS_FD_MAX - 1, &plain_ops, INT32_MAX, 0, 0, 0);
	assert_true(tcs_fd_of(TCS_FD_MAX - 1, &e));
	assert_ptr_equal(e.ops, &plain_ops);
	assert_int_equal(e.handle, INT32_MAX);
}

static void test_forget_lets_the_kind_go_once(void **state)
{
	(void)state;
	struct tcs_fd e;
	set(5, &served_ops, 9, 2, 4, 0);
	assert_int_equal(tcs_fds_served(), 1);
	tcs_fd_forget(5);
	assert_false(tcs_fd_of(5, &e));
	assert_int_equal(seen.forgets, 1);
	assert_int_equal(seen.last_fd, 5);
	assert_int_equal(seen.last.handle, 9);
	assert_int_equal(seen.last.slot, 4);
	assert_int_equal(tcs_fds_served(), 0);
	tcs_fd_forget(5); /* closed twice: nothing more */
	assert_int_equal(seen.forgets, 1);
}

static void test_a_copy_shares_the_kind_s_state(void **state)
{
	(void)state;
	struct tcs_fd e;
	set(5, &served_ops, 9, 2, 4, 1);
	set(8, &plain_ops, -1, 0, 0, 0);
	tcs_fd_copy(5, 8); /* dup2(5, 8): 8's old entry forgotten first */
	assert_int_equal(seen.copies, 1);
	assert_int_equal(seen.last_fd, 8);
	assert_true(tcs_fd_of(8, &e));
	assert_ptr_equal(e.ops, &served_ops);
	assert_int_equal(e.handle, 9);
	assert_int_equal(e.slot, 4);
	assert_int_equal(e.flags, 1);
	assert_int_equal(tcs_fds_served(), 2);
	tcs_fd_copy(5, 5); /* dup2 onto itself: nothing */
	assert_int_equal(seen.copies, 1);
	tcs_fd_copy(3, 8); /* a copy of an fd not tcs's is not tcs's */
	assert_false(tcs_fd_of(8, &e));
	assert_int_equal(seen.forgets, 1);
	assert_int_equal(tcs_fds_served(), 1);
}

static void test_a_range_is_forgotten_and_a_fork_put_right(void **state)
{
	(void)state;
	set(10, &served_ops, 1, 0, 0, 0);
	set(11, &plain_ops, -1, 0, 0, 0);
	set(12, &served_ops, 2, 0, 1, 0);
	assert_int_equal(tcs_fd_find(&served_ops, 1), 12);
	assert_int_equal(tcs_fd_find(&served_ops, 2), -1);
	tcs_fds_after_fork();
	assert_int_equal(seen.after_forks, 2); /* the plain kind has none */
	tcs_fd_forget_range(11, UINT32_MAX);
	assert_int_equal(seen.forgets, 1);
	assert_int_equal(tcs_fd_find(&served_ops, 1), -1);
	assert_int_equal(tcs_fd_find(&served_ops, 0), 10);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup(test_an_fd_not_set_is_not_tcs_s, reset),
		cmocka_unit_test_setup(test_an_entry_reads_back_whole, reset),
		cmocka_unit_test_setup(test_forget_lets_the_kind_go_once, reset),
		cmocka_unit_test_setup(test_a_copy_shares_the_kind_s_state, reset),
		cmocka_unit_test_setup(test_a_range_is_forgotten_and_a_fork_put_right, reset),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
