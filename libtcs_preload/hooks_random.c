/* Randomness hooks: getrandom and getentropy draw from the process's
 * seeded stream under --seed (random.c), and from the kernel otherwise.
 * (Reads of /dev/urandom and /dev/random: the I/O hooks, hooks_io.c.) */
#include <sys/random.h>

#include "random.h"
#include "raw_syscall.h"

TCS_EXPORT ssize_t getrandom(void *buf, size_t n, unsigned flags)
{
	return tcs_errno_result(tcs_getrandom(buf, n, flags));
}

TCS_EXPORT int getentropy(void *buf, size_t n)
{
	if (n > 256)
		return tcs_errno_result(-EIO);
	for (size_t done = 0; done < n;) {
		long r = tcs_getrandom((char *)buf + done, n - done, 0);
		if (r == -EINTR)
			continue;
		if (r < 0)
			return tcs_errno_result(r);
		done += (size_t)r;
	}
	return 0;
}
