/* I/O hooks: read, readv, __read_chk, write, writev. What the fd is
 * decides who serves the call: a virtual timerfd's read its own hooks
 * (hooks_timerfd.c), a device's read or write the device table
 * (devices.c), which makes the one round trip it needs, a random device's
 * read under --seed the seeded stream (random.c); anything else goes
 * straight to the kernel. */
#include <sys/uio.h>

#include "devices.h"
#include "hooks_timerfd.h"
#include "random.h"
#include "raw_syscall.h"
#include "timerfds.h"

TCS_EXPORT ssize_t read(int fd, void *buf, size_t n)
{
	if (tcs_active()) {
		if (tcs_vtimer_of(fd))
			return tcs_errno_result(tcs_timerfd_read(fd, buf, n));
		if (tcs_device_handle(fd) >= 0)
			return tcs_errno_result(tcs_device_read(fd, buf, n));
		if (tcs_random_fd(fd))
			return tcs_errno_result(tcs_random_read(buf, n));
	}
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
	if (tcs_active() && tcs_device_handle(fd) >= 0)
		return tcs_errno_result(tcs_device_readv(fd, iov, n));
	if (tcs_active() && tcs_random_fd(fd))
		return tcs_errno_result(tcs_random_readv(iov, n));
	return tcs_errno_result(tcs_sys3(SYS_readv, fd, iov, n));
}

TCS_EXPORT ssize_t write(int fd, const void *buf, size_t n)
{
	if (tcs_device_handle(fd) < 0) /* most writes: no device */
		return tcs_errno_result(tcs_sys3(SYS_write, fd, buf, n));
	return tcs_errno_result(tcs_device_write(fd, buf, n));
}

TCS_EXPORT ssize_t writev(int fd, const struct iovec *iov, int n)
{
	if (tcs_device_handle(fd) < 0)
		return tcs_errno_result(tcs_sys3(SYS_writev, fd, iov, n));
	return tcs_errno_result(tcs_device_writev(fd, iov, n));
}
