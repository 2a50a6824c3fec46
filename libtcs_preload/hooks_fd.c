/* Descriptor hooks: keep the runtime's own fds (channel and clock page)
 * alive in programs that close every descriptor or dup2 over them (to the
 * program those fds look like they were never open: EBADF), and keep the
 * fd table (fd_table.h) true: what a closed fd was is forgotten, a
 * duplicate is what its original is. */
#include <fcntl.h>
#include <limits.h>
#include <linux/close_range.h>

#include "fd_table.h"
#include "raw_syscall.h"
#include "thread_channels.h"

TCS_EXPORT int close(int fd)
{
	if (tcs_is_runtime_fd(fd))
		return tcs_errno_result(-EBADF);
	tcs_fd_forget(fd);
	return tcs_errno_result(tcs_sys1(SYS_close, fd));
}

/* close_range over [first, last], stepping around the runtime's fds (device
 * fds it closes are forgotten as close() forgets them). */
static long tcs_close_range(unsigned first, unsigned last, unsigned flags)
{
	int mine[2 + 256];
	mine[0] = tcs_rt.channel_fd;
	mine[1] = tcs_rt.page_fd;
	int n = 2 + tcs_thread_channels(mine + 2, 256);
	for (int i = 1; i < n; i++) /* a handful: insertion sort */
		for (int j = i; j > 0 && mine[j - 1] > mine[j]; j--) {
			int t = mine[j];
			mine[j] = mine[j - 1];
			mine[j - 1] = t;
		}
	for (int i = 0; i < n && first <= last; i++) {
		if (mine[i] < 0 || (unsigned)mine[i] < first || (unsigned)mine[i] > last)
			continue;
		if ((unsigned)mine[i] > first) {
			long r = tcs_sys3(SYS_close_range, first, (unsigned)mine[i] - 1, flags);
			if (r < 0)
				return r;
		}
		if ((unsigned)mine[i] == UINT_MAX)
			return 0;
		first = (unsigned)mine[i] + 1;
	}
	return first <= last ? tcs_sys3(SYS_close_range, first, last, flags) : 0;
}

TCS_EXPORT int close_range(unsigned first, unsigned last, int flags)
{
	if (first > last)
		return tcs_errno_result(-EINVAL);
	if (!(flags & CLOSE_RANGE_CLOEXEC))
		tcs_fd_forget_range(first, last);
	return tcs_errno_result(tcs_close_range(first, last, (unsigned)flags));
}

TCS_EXPORT void closefrom(int lowfd)
{
	tcs_fd_forget_range(lowfd < 0 ? 0 : (unsigned)lowfd, UINT_MAX);
	tcs_close_range(lowfd < 0 ? 0 : (unsigned)lowfd, UINT_MAX, 0);
}

TCS_EXPORT int dup2(int oldfd, int newfd)
{
	if (tcs_is_runtime_fd(newfd) || tcs_is_runtime_fd(oldfd))
		return tcs_errno_result(-EBADF);
	if (oldfd == newfd) /* dup2 checks oldfd and returns it; dup3 would fail */
		return tcs_errno_result(tcs_sys3(SYS_fcntl, oldfd, F_GETFD, 0) < 0 ? -EBADF : oldfd);
	return dup3(oldfd, newfd, 0);
}

TCS_EXPORT int dup(int oldfd)
{
	long r = tcs_sys1(SYS_dup, oldfd);
	if (r >= 0)
		tcs_fd_copy(oldfd, (int)r);
	return tcs_errno_result(r);
}

TCS_EXPORT int dup3(int oldfd, int newfd, int flags)
{
	if (tcs_is_runtime_fd(newfd) || tcs_is_runtime_fd(oldfd))
		return tcs_errno_result(-EBADF);
	long r = tcs_sys3(SYS_dup3, oldfd, newfd, flags);
	if (r >= 0)
		tcs_fd_copy(oldfd, newfd);
	return tcs_errno_result(r);
}
