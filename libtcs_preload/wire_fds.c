/* Wire fds' state (see wire_fds.h): a few slots, which an fd's entry in
 * the fd table names. Programs open a handful of buses, so 64 slots are
 * plenty; an open beyond them fails with EMFILE. A slot is taken and let
 * go by the thread that opens, dups or closes a wire's fd; a signal
 * handler's open may interrupt it, so a slot is claimed with one atomic
 * step. */
#include "wire_fds.h"

#define TCS_WIRE_SLOTS 64

static struct tcs_wire_fd tcs_wire_slots[TCS_WIRE_SLOTS];
static uint16_t tcs_wire_refs[TCS_WIRE_SLOTS]; /* fds on each slot; 0: free */

static int tcs_is_wire(const struct tcs_fd *e)
{
	unsigned k = e->ops->kind;
	return k == TCS_FD_SERIAL || k == TCS_FD_I2C || k == TCS_FD_CAN;
}

struct tcs_wire_fd *tcs_wire_of(const struct tcs_fd *e)
{
	return &tcs_wire_slots[e->slot % TCS_WIRE_SLOTS];
}

struct tcs_wire_fd *tcs_wire_fd(int fd)
{
	struct tcs_fd e;
	if (!tcs_fd_of(fd, &e) || !tcs_is_wire(&e))
		return NULL;
	return tcs_wire_of(&e);
}

int tcs_wire_slot_new(void)
{
	for (int i = 0; i < TCS_WIRE_SLOTS; i++) {
		uint16_t free_slot = 0;
		if (!__atomic_compare_exchange_n(&tcs_wire_refs[i], &free_slot, 1, 0, __ATOMIC_ACQUIRE, __ATOMIC_RELAXED))
			continue;
		struct tcs_wire_fd *w = &tcs_wire_slots[i];
		__builtin_memset(w, 0, sizeof *w);
		w->i2c_addr = 0xffff;
		return i;
	}
	return -EMFILE;
}

void tcs_wire_forget(int fd, const struct tcs_fd *e)
{
	(void)fd;
	__atomic_sub_fetch(&tcs_wire_refs[e->slot % TCS_WIRE_SLOTS], 1, __ATOMIC_RELEASE);
}

void tcs_wire_copy(int to, const struct tcs_fd *e)
{
	(void)to;
	__atomic_add_fetch(&tcs_wire_refs[e->slot % TCS_WIRE_SLOTS], 1, __ATOMIC_RELAXED);
}
