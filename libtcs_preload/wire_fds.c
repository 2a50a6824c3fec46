/* Wire fds' state (see wire_fds.h): a few slots, found through a byte per
 * fd. Programs open a handful of buses, so 64 slots are plenty; an open
 * beyond them fails with EMFILE. */
#include "wire_fds.h"

#include "devices.h"

#define TCS_WIRE_SLOTS 64

static struct tcs_wire_fd tcs_wire_slots[TCS_WIRE_SLOTS];
static uint8_t tcs_wire_slot_of[TCS_DEVICE_FD_MAX]; /* slot + 1; 0: none */
static uint16_t tcs_wire_refs[TCS_WIRE_SLOTS];        /* fds on each slot */

struct tcs_wire_fd *tcs_wire_fd(int fd)
{
	if (fd < 0 || fd >= TCS_DEVICE_FD_MAX || tcs_wire_slot_of[fd] == 0)
		return NULL;
	return &tcs_wire_slots[tcs_wire_slot_of[fd] - 1];
}

struct tcs_wire_fd *tcs_wire_fd_new(int fd, uint32_t kind)
{
	if (fd < 0 || fd >= TCS_DEVICE_FD_MAX)
		return NULL;
	tcs_wire_fd_forget(fd);
	for (int i = 0; i < TCS_WIRE_SLOTS; i++) {
		struct tcs_wire_fd *w = &tcs_wire_slots[i];
		if (tcs_wire_refs[i])
			continue;
		tcs_wire_refs[i] = 1;
		__builtin_memset(w, 0, sizeof *w);
		w->fd = fd;
		w->kind = kind;
		w->i2c_addr = 0xffff;
		tcs_wire_slot_of[fd] = (uint8_t)(i + 1);
		return w;
	}
	return NULL;
}

void tcs_wire_fd_forget(int fd)
{
	if (fd < 0 || fd >= TCS_DEVICE_FD_MAX || tcs_wire_slot_of[fd] == 0)
		return;
	tcs_wire_refs[tcs_wire_slot_of[fd] - 1]--;
	tcs_wire_slot_of[fd] = 0;
}

/* A dup shares the open file, as the kernel's does: one state for both. */
void tcs_wire_fd_copy(int from, int to)
{
	if (from < 0 || from >= TCS_DEVICE_FD_MAX || to < 0 || to >= TCS_DEVICE_FD_MAX)
		return;
	if (tcs_wire_slot_of[from] == 0 || from == to)
		return;
	tcs_wire_fd_forget(to);
	tcs_wire_slot_of[to] = tcs_wire_slot_of[from];
	tcs_wire_refs[tcs_wire_slot_of[to] - 1]++;
}
