/* The preload's one fd table (fd_table.c): for each fd below TCS_FD_MAX,
 * what tcs knows it to be (a device, a wire, a virtual timerfd, a seeded
 * random device, or nothing) and the operations that serve it. The hooks
 * ask the table and call the entry's operations; no hook asks a kind by
 * name. Nothing else in the library keeps anything per fd.
 *
 * Who writes an entry, and how a reader sees it whole:
 *   - an entry is one 64-bit word (struct tcs_fd packed: kind, flags,
 *     device, slot, handle), stored whole with one atomic store and read
 *     whole with one atomic load: a reader never sees half of one, whether
 *     it is another thread or a signal handler that interrupted the writer;
 *   - it is written only by the hook that changes what the fd is (open,
 *     socket, timerfd_create, dup*, close*, a child putting right what it
 *     inherited), on the thread that made the call, after the kernel made
 *     the fd what it now is (open, dup) or before the kernel closes it
 *     (close): a reader at any moment finds the entry the fd had, or the
 *     one it gets; two writers of one fd at once (a handler closing the fd
 *     its flow dups onto) race on the fd itself, as they do in the kernel;
 *   - a kind's operations are a constant struct, named in a table of kinds
 *     that is written (always with the same pointer) before the first word
 *     naming the kind is stored, and never changed: a word read names its
 *     operations;
 *   - the table takes no lock: a hook in a handler reads it while the flow
 *     it interrupted writes it, and neither waits for the other. A kind's
 *     own state beside it (a timer's expiry, a wire's settings) is the
 *     kind's: where it takes a lock for it, that is spin_lock.h's tcs_lock,
 *     which blocks every signal while held, so no handler's hook ever finds
 *     it held (docs/DESIGN.md, "Re-entrancy").
 * A read of an fd that is not tcs's costs one bounds check and one load. */
#ifndef TCS_PRELOAD_FD_TABLE_H
#define TCS_PRELOAD_FD_TABLE_H

#include <stddef.h>
#include <stdint.h>

#include "runtime.h"

struct iovec;
struct msghdr;
struct sockaddr;
struct termios;

/* fds tcs serves live below this: open() moves a device's fd below it if
 * it must, and a timerfd beyond it is refused. */
#define TCS_FD_MAX 4096

/* What an fd is (struct tcs_fd_ops' kind). */
enum tcs_fd_kind {
	TCS_FD_NONE = 0,
	TCS_FD_SENSOR,   /* a device the controller reads records from (devices.c) */
	TCS_FD_ACTUATOR, /* a device the controller writes records to (devices.c) */
	TCS_FD_SERIAL,   /* a wire: a serial line (serial.c) */
	TCS_FD_I2C,      /* a wire: an I2C bus (i2c.c) */
	TCS_FD_CAN,      /* a wire: a CAN_RAW socket (can.c) */
	TCS_FD_TIMERFD,  /* a virtual timerfd (timerfds.c) */
	TCS_FD_RANDOM,   /* /dev/urandom or /dev/random under --seed (random.c) */
	TCS_FD_KINDS
};

/* One entry, as read whole. */
struct tcs_fd {
	const struct tcs_fd_ops *ops; /* NULL: not tcs's */
	int handle;    /* a device's handle at the coordinator */
	unsigned dev;  /* a device's index in the device table */
	unsigned slot; /* the kind's own state: its slot in the kind's table */
	unsigned flags; /* the kind's own bits */
};

/* What a kind does for the hooks. Each call gets the fd and its entry as
 * the hook read it (one load: the kind need not read the table again).
 * The result, or -errno. A NULL operation is the kernel's own call (or,
 * for the table's, nothing to do). */
struct tcs_fd_ops {
	unsigned kind;   /* enum tcs_fd_kind */
	int served;      /* a device the coordinator serves: what is due on it
			    is put in its fd (one sync for all) before a
			    multiplexer asks the kernel what is ready */
	unsigned access; /* a device: the access modes (1 << O_RDONLY, ...) it
			    may be opened with */
	int fork_access; /* a device: the access mode a child opens it with again */

	long (*read)(int fd, const struct tcs_fd *e, void *buf, size_t n);
	long (*readv)(int fd, const struct tcs_fd *e, const struct iovec *iov, int n);
	long (*write)(int fd, const struct tcs_fd *e, const void *buf, size_t n);
	long (*writev)(int fd, const struct tcs_fd *e, const struct iovec *iov, int n);
	long (*recvmsg)(int fd, const struct tcs_fd *e, struct msghdr *msg, int flags);
	long (*sendmsg)(int fd, const struct tcs_fd *e, const struct msghdr *msg, int flags);
	long (*bind)(int fd, const struct tcs_fd *e, const struct sockaddr *addr, uint32_t len);
	long (*getsockname)(int fd, const struct tcs_fd *e, struct sockaddr *addr, uint32_t *len);
	long (*setsockopt)(int fd, const struct tcs_fd *e, int level, int name, const void *value, uint32_t len);
	long (*getsockopt)(int fd, const struct tcs_fd *e, int level, int name, void *value, uint32_t *len);
	long (*ioctl)(int fd, const struct tcs_fd *e, unsigned long request, void *arg);
	long (*tcgetattr)(int fd, const struct tcs_fd *e, struct termios *t);
	long (*tcsetattr)(int fd, const struct tcs_fd *e, int when, const struct termios *t);
	long (*tcflush)(int fd, const struct tcs_fd *e, int queue);
	long (*tcdrain)(int fd, const struct tcs_fd *e);

	/* A device's fd, just opened as handle of device dev (or opened again
	 * in a child, in place of the inherited one): sets up the kind's state
	 * and the entry (tcs_fd_set). 0 or -errno. */
	long (*opened)(int fd, int handle, unsigned dev);
	/* The entry e of fd is gone (closed, or replaced): the kind lets go of
	 * its state. */
	void (*forget)(int fd, const struct tcs_fd *e);
	/* fd `to` becomes a copy of e (a dup): the kind's state is shared, as
	 * the kernel shares the open file. */
	void (*copy)(int to, const struct tcs_fd *e);
	/* In a new child, registered: what it inherited of fd put right. */
	void (*after_fork)(int fd, const struct tcs_fd *e);
};

/* The table (fd_table.c): read through tcs_fd_of only. */
extern uint64_t tcs_fd_words[TCS_FD_MAX] TCS_HIDDEN;
extern const struct tcs_fd_ops *tcs_fd_kind_ops[TCS_FD_KINDS] TCS_HIDDEN;

/* The entry of fd in *e: 1, or 0 when fd is not tcs's. Inline: every I/O
 * hook asks it first. */
static inline __attribute__((always_inline)) int tcs_fd_of(int fd, struct tcs_fd *e)
{
	if ((unsigned)fd >= TCS_FD_MAX)
		return 0;
	uint64_t w = __atomic_load_n(&tcs_fd_words[fd], __ATOMIC_ACQUIRE);
	if (__builtin_expect(w == 0, 1))
		return 0;
	e->ops = __atomic_load_n(&tcs_fd_kind_ops[w & 0xff], __ATOMIC_RELAXED);
	e->flags = (unsigned)(w >> 8) & 0xff;
	e->dev = (unsigned)(w >> 16) & 0xff;
	e->slot = (unsigned)(w >> 24) & 0xff;
	e->handle = (int)(int32_t)(uint32_t)(w >> 32);
	return 1;
}

/* fd (below TCS_FD_MAX) becomes e (e->ops not NULL; dev, slot and flags
 * below 256), in place of what it was (forgotten first). */
void tcs_fd_set(int fd, const struct tcs_fd *e) TCS_HIDDEN;
/* fd was closed: forgotten. Any fd; nothing when it is not tcs's. */
void tcs_fd_forget(int fd) TCS_HIDDEN;
/* Every fd in [first, last] forgotten (close_range, closefrom). */
void tcs_fd_forget_range(unsigned first, unsigned last) TCS_HIDDEN;
/* `to` became a copy of `from` (dup, dup2, dup3): what it was is
 * forgotten, and it is what `from` is. */
void tcs_fd_copy(int from, int to) TCS_HIDDEN;
/* How many fds are devices the coordinator serves (then a multiplexer
 * syncs them first). */
int tcs_fds_served(void) TCS_HIDDEN;
/* The lowest fd whose entry is of ops with this slot, or -1 (a kind's
 * state shared by several fds finds another of them). */
int tcs_fd_find(const struct tcs_fd_ops *ops, unsigned slot) TCS_HIDDEN;
/* In a new child, registered: each fd's after_fork. */
void tcs_fds_after_fork(void) TCS_HIDDEN;
/* readv(2) and writev(2) as the kernel makes them of a file that has only
 * read and write: one call of the kind's read or write per buffer, until
 * one comes short. */
long tcs_fd_readv_by_reads(int fd, const struct tcs_fd *e, const struct iovec *iov, int n) TCS_HIDDEN;
long tcs_fd_writev_by_writes(int fd, const struct tcs_fd *e, const struct iovec *iov, int n) TCS_HIDDEN;

#endif
