/* The one fd table (fd_table.h): a word per fd, and what closing,
 * duplicating and forking do to it, once for every kind through the
 * entry's operations. It stands below every kind: it calls a kind only
 * through the operations the kind's entry names, and takes no lock. */
#include "fd_table.h"

#include <sys/uio.h>

uint64_t tcs_fd_words[TCS_FD_MAX];
const struct tcs_fd_ops *tcs_fd_kind_ops[TCS_FD_KINDS];
static int tcs_fd_served_count;

static uint64_t tcs_fd_pack(const struct tcs_fd *e)
{
	return (uint64_t)(e->ops->kind & 0xff) | (uint64_t)(e->flags & 0xff) << 8 | (uint64_t)(e->dev & 0xff) << 16 |
	       (uint64_t)(e->slot & 0xff) << 24 | (uint64_t)(uint32_t)e->handle << 32;
}

void tcs_fd_forget(int fd)
{
	struct tcs_fd e;
	if (!tcs_fd_of(fd, &e))
		return;
	/* Gone from the table before the kind lets go of its state: a kind
	 * looking for another fd of its state (tcs_fd_find) finds none here. */
	__atomic_store_n(&tcs_fd_words[fd], 0, __ATOMIC_RELEASE);
	if (e.ops->served)
		__atomic_sub_fetch(&tcs_fd_served_count, 1, __ATOMIC_RELAXED);
	if (e.ops->forget)
		e.ops->forget(fd, &e);
}

void tcs_fd_set(int fd, const struct tcs_fd *e)
{
	if ((unsigned)fd >= TCS_FD_MAX)
		return;
	tcs_fd_forget(fd);
	__atomic_store_n(&tcs_fd_kind_ops[e->ops->kind], e->ops, __ATOMIC_RELAXED);
	if (e->ops->served)
		__atomic_add_fetch(&tcs_fd_served_count, 1, __ATOMIC_RELAXED);
	__atomic_store_n(&tcs_fd_words[fd], tcs_fd_pack(e), __ATOMIC_RELEASE);
}

void tcs_fd_forget_range(unsigned first, unsigned last)
{
	for (unsigned fd = first; fd <= last && fd < TCS_FD_MAX; fd++)
		tcs_fd_forget((int)fd);
}

void tcs_fd_copy(int from, int to)
{
	struct tcs_fd e;
	if (from == to || (unsigned)to >= TCS_FD_MAX)
		return;
	tcs_fd_forget(to);
	if (!tcs_fd_of(from, &e))
		return;
	if (e.ops->copy)
		e.ops->copy(to, &e);
	tcs_fd_set(to, &e);
}

int tcs_fds_served(void)
{
	return __atomic_load_n(&tcs_fd_served_count, __ATOMIC_RELAXED);
}

int tcs_fd_find(const struct tcs_fd_ops *ops, unsigned slot)
{
	struct tcs_fd e;
	for (int fd = 0; fd < TCS_FD_MAX; fd++)
		if (tcs_fd_of(fd, &e) && e.ops == ops && e.slot == slot)
			return fd;
	return -1;
}

void tcs_fds_after_fork(void)
{
	struct tcs_fd e;
	for (int fd = 0; fd < TCS_FD_MAX; fd++)
		if (tcs_fd_of(fd, &e) && e.ops->after_fork)
			e.ops->after_fork(fd, &e);
}

/* One call per buffer, as the kernel's readv/writev of such a file does;
 * what was done, or the first error if nothing was. */
static long tcs_fd_each_buffer(int fd, const struct tcs_fd *e, const struct iovec *iov, int n, int writing)
{
	long done = 0;
	for (int i = 0; i < n; i++) {
		long r = writing ? e->ops->write(fd, e, iov[i].iov_base, iov[i].iov_len)
				 : e->ops->read(fd, e, iov[i].iov_base, iov[i].iov_len);
		if (r < 0)
			return done > 0 ? done : r;
		done += r;
		if ((size_t)r < iov[i].iov_len)
			break;
	}
	return done;
}

long tcs_fd_readv_by_reads(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	return tcs_fd_each_buffer(fd, e, iov, n, 0);
}

long tcs_fd_writev_by_writes(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	return tcs_fd_each_buffer(fd, e, iov, n, 1);
}
