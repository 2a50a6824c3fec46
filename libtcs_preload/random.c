/* --seed in the preload (random.h). The stream's position is the clock
 * page's random_drawn, taken a block at a time with one atomic add, so
 * threads never draw the same bytes and an exec'd image goes on where its
 * predecessor stopped. A random device's fd is an entry of the fd table
 * (fd_table.h) whose reads draw the stream: below TCS_FD_MAX, beyond it
 * real. */
#include "random.h"

#include <limits.h>
#include <sys/random.h>
#include <sys/uio.h>

#include "raw_syscall.h"
#include "tcs/random_stream.h"

/* What getrandom(2) gives at most in one call. */
#define TCS_GETRANDOM_MAX (INT_MAX >> 6)

int tcs_seeded(void)
{
	return tcs_active() && tcs_rt.page->random_key != 0;
}

void tcs_random_fill(void *buf, size_t n)
{
	struct tcs_clock_page *p = tcs_rt.page;
	uint64_t blocks = (n + 7) / 8;
	uint64_t i = __atomic_fetch_add(&p->random_drawn, blocks, __ATOMIC_RELAXED);
	unsigned char *out = buf;
	for (; n > 0; i++) {
		uint64_t b = tcs_random_block(p->random_key, i);
		size_t k = n < 8 ? n : 8;
		for (size_t j = 0; j < k; j++)
			out[j] = (unsigned char)(b >> (8 * j));
		out += k;
		n -= k;
	}
}

long tcs_getrandom(void *buf, size_t n, unsigned flags)
{
	if (!tcs_seeded())
		return tcs_sys3(SYS_getrandom, buf, n, flags);
	if (flags & ~(unsigned)(GRND_NONBLOCK | GRND_RANDOM | GRND_INSECURE))
		return -EINVAL;
	if ((flags & (GRND_RANDOM | GRND_INSECURE)) == (GRND_RANDOM | GRND_INSECURE))
		return -EINVAL;
	if (n > TCS_GETRANDOM_MAX)
		n = TCS_GETRANDOM_MAX;
	tcs_random_fill(buf, n);
	return (long)n;
}

int tcs_random_path(const char *path)
{
	return path && (tcs_str_equal(path, "/dev/urandom") || tcs_str_equal(path, "/dev/random"));
}

/* read(2) and readv(2) of such an fd: all that was asked. */
static long tcs_random_read(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	(void)fd, (void)e;
	if (n > SSIZE_MAX)
		n = SSIZE_MAX;
	tcs_random_fill(buf, n);
	return (long)n;
}

static long tcs_random_readv(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	(void)fd, (void)e;
	if (n < 0 || n > IOV_MAX)
		return -EINVAL;
	long total = 0;
	for (int i = 0; i < n; i++) {
		tcs_random_fill(iov[i].iov_base, iov[i].iov_len);
		total += (long)iov[i].iov_len;
	}
	return total;
}

/* What is written to a random device, its ioctls, and fork: the kernel's
 * (a write mixes into the kernel's pool, which the stream never reads). */
static const struct tcs_fd_ops tcs_random_ops = {
	.kind = TCS_FD_RANDOM,
	.read = tcs_random_read,
	.readv = tcs_random_readv,
};

void tcs_random_fd_opened(int fd)
{
	struct tcs_fd e = { &tcs_random_ops, -1, 0, 0, 0 };
	tcs_fd_set(fd, &e);
}
