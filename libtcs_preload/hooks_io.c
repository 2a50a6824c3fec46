/* I/O hooks: read, readv, __read_chk, write, writev. What the fd is (its
 * entry in the fd table, fd_table.h) decides who serves the call: the
 * entry's operations (a device's read or write, with the one round trip it
 * needs; a virtual timerfd's read; a random device's under --seed), or,
 * for every fd that is not tcs's, the kernel, after one bounds check and
 * one load. */
#include <sys/uio.h>

#include "fd_table.h"
#include "raw_syscall.h"

TCS_EXPORT ssize_t read(int fd, void *buf, size_t n)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->read && tcs_active())
		return tcs_errno_result(e.ops->read(fd, &e, buf, n));
	return tcs_errno_result(tcs_sys3(SYS_read, fd, buf, n));
}

/* The _FORTIFY_SOURCE variant (declared by no public header). */
TCS_EXPORT long __read_chk(int fd, void *buf, size_t n, size_t buflen);
TCS_EXPORT long __read_chk(int fd, void *buf, size_t n, size_t buflen)
{
	(void)buflen;
	return read(fd, buf, n);
}

TCS_EXPORT ssize_t readv(int fd, const struct iovec *iov, int n)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->readv && tcs_active())
		return tcs_errno_result(e.ops->readv(fd, &e, iov, n));
	return tcs_errno_result(tcs_sys3(SYS_readv, fd, iov, n));
}

/* A write goes to the kind even when tcs is not active (a child the
 * coordinator did not take on): a device's write then passes through. */
TCS_EXPORT ssize_t write(int fd, const void *buf, size_t n)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->write)
		return tcs_errno_result(e.ops->write(fd, &e, buf, n));
	return tcs_errno_result(tcs_sys3(SYS_write, fd, buf, n));
}

TCS_EXPORT ssize_t writev(int fd, const struct iovec *iov, int n)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->writev)
		return tcs_errno_result(e.ops->writev(fd, &e, iov, n));
	return tcs_errno_result(tcs_sys3(SYS_writev, fd, iov, n));
}
