/* --seed in the preload (random.h). The stream's position is the clock
 * page's random_drawn, taken a block at a time with one atomic add, so
 * threads never draw the same bytes and an exec'd image goes on where its
 * predecessor stopped. Random-device fds are a bitmap like the device
 * table's (devices.h): below TCS_DEVICE_FD_MAX, beyond it real. */
#include "random.h"

#include <limits.h>
#include <sys/random.h>
#include <sys/uio.h>

#include "devices.h"
#include "raw_syscall.h"
#include "tcs/random_stream.h"

/* What getrandom(2) gives at most in one call. */
#define TCS_GETRANDOM_MAX (INT_MAX >> 6)

static uint64_t tcs_random_fds[TCS_DEVICE_FD_MAX / 64];

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

void tcs_random_fd_opened(int fd)
{
	if (fd >= 0 && fd < TCS_DEVICE_FD_MAX)
		__atomic_or_fetch(&tcs_random_fds[fd / 64], 1ull << (fd % 64), __ATOMIC_RELAXED);
}

int tcs_random_fd(int fd)
{
	if (fd < 0 || fd >= TCS_DEVICE_FD_MAX)
		return 0;
	return (__atomic_load_n(&tcs_random_fds[fd / 64], __ATOMIC_RELAXED) >> (fd % 64)) & 1;
}

void tcs_random_forget(int fd)
{
	if (fd >= 0 && fd < TCS_DEVICE_FD_MAX)
		__atomic_and_fetch(&tcs_random_fds[fd / 64], ~(1ull << (fd % 64)), __ATOMIC_RELAXED);
}

void tcs_random_copy(int from, int to)
{
	if (tcs_random_fd(from))
		tcs_random_fd_opened(to);
}

long tcs_random_read(void *buf, size_t n)
{
	if (n > SSIZE_MAX)
		n = SSIZE_MAX;
	tcs_random_fill(buf, n);
	return (long)n;
}

long tcs_random_readv(const struct iovec *iov, int n)
{
	if (n < 0 || n > IOV_MAX)
		return -EINVAL;
	long total = 0;
	for (int i = 0; i < n; i++) {
		tcs_random_fill(iov[i].iov_base, iov[i].iov_len);
		total += (long)iov[i].iov_len;
	}
	return total;
}
