/* io_uring_probe: asks the kernel for an io_uring twice through syscall(),
 * as a program that tries io_uring and falls back does, and prints what
 * each call returned (ret, and errno's name when it failed). Under tcs
 * both fail with ENOSYS (tcs-run(1), Direct system calls: its waits would
 * run in real time). */
#include <errno.h>
#include <linux/io_uring.h>
#include <stdio.h>
#include <string.h>
#include <sys/syscall.h>
#include <unistd.h>

static const char *errno_name(int e)
{
	switch (e) {
	case ENOSYS: return "ENOSYS";
	case EPERM: return "EPERM";
	case EINVAL: return "EINVAL";
	case ENOMEM: return "ENOMEM";
	default: return "other";
	}
}

int main(void)
{
	for (int i = 1; i <= 2; i++) {
		struct io_uring_params p;
		memset(&p, 0, sizeof p);
		errno = 0;
		long r = syscall(SYS_io_uring_setup, 4, &p);
		int e = errno;
		printf("call%d_ret=%ld call%d_errno=%s\n", i, r < 0 ? -1L : 0L, i, r < 0 ? errno_name(e) : "none");
		if (r >= 0)
			close((int)r);
	}
	return 0;
}
