/* Device hooks: open/openat/fopen (with their 64 and fortified variants)
 * of a scenario's device paths give a real fd the coordinator serves
 * (device_open.c); reads and writes of it are the I/O hooks' (hooks_io.c);
 * termios calls and ioctls on an fd tcs serves are its entry's operations
 * (fd_table.h). /dev/urandom and /dev/random under --seed open as
 * themselves, their fds in the fd table for the I/O hooks to read from the
 * seeded stream (random.c). Everything else passes straight to the
 * kernel, or to libc. */
/* Both open() and open64() are defined here: the headers must not rename
 * one to the other (meson builds with _FILE_OFFSET_BITS=64). */
#undef _FILE_OFFSET_BITS
#include <fcntl.h>
#include <stdarg.h>
#include <string.h>
#include <stdio.h>
#include <sys/ioctl.h>
#include <termios.h>

#include "can_ifaces.h"
#include "device_open.h"
#include "fd_table.h"
#include "random.h"
#include "raw_syscall.h"
#include "real.h"

/* ---- open ---------------------------------------------------------------- */

static long tcs_openat(int dirfd, const char *path, int flags, mode_t mode)
{
	int dev = tcs_device_lookup(path);
	if (dev >= 0)
		return tcs_device_open(dev, flags);
	long fd = tcs_sys4(SYS_openat, dirfd, path, flags, mode);
	if (fd >= 0 && tcs_random_path(path) && tcs_seeded())
		tcs_random_fd_opened((int)fd);
	return fd;
}

#define TCS_MODE_ARG(flags, mode)                                  \
	do {                                                       \
		if ((flags) & (O_CREAT | __O_TMPFILE)) {           \
			va_list ap;                                \
			va_start(ap, flags);                       \
			mode = (mode_t)va_arg(ap, unsigned int);   \
			va_end(ap);                                \
		}                                                  \
	} while (0)

TCS_EXPORT int open(const char *path, int flags, ...)
{
	mode_t mode = 0;
	TCS_MODE_ARG(flags, mode);
	return tcs_errno_result(tcs_openat(AT_FDCWD, path, flags, mode));
}

TCS_EXPORT int open64(const char *path, int flags, ...)
{
	mode_t mode = 0;
	TCS_MODE_ARG(flags, mode);
	return tcs_errno_result(tcs_openat(AT_FDCWD, path, flags | O_LARGEFILE, mode));
}

TCS_EXPORT int openat(int dirfd, const char *path, int flags, ...)
{
	mode_t mode = 0;
	TCS_MODE_ARG(flags, mode);
	return tcs_errno_result(tcs_openat(dirfd, path, flags, mode));
}

TCS_EXPORT int openat64(int dirfd, const char *path, int flags, ...)
{
	mode_t mode = 0;
	TCS_MODE_ARG(flags, mode);
	return tcs_errno_result(tcs_openat(dirfd, path, flags | O_LARGEFILE, mode));
}

/* _FORTIFY_SOURCE variants: no mode argument (O_CREAT is a compile error);
 * declared by no public header. */
TCS_EXPORT int __open_2(const char *path, int flags);
TCS_EXPORT int __open64_2(const char *path, int flags);
TCS_EXPORT int __openat_2(int dirfd, const char *path, int flags);
TCS_EXPORT int __openat64_2(int dirfd, const char *path, int flags);

TCS_EXPORT int __open_2(const char *path, int flags)
{
	return tcs_errno_result(tcs_openat(AT_FDCWD, path, flags, 0));
}

TCS_EXPORT int __open64_2(const char *path, int flags)
{
	return tcs_errno_result(tcs_openat(AT_FDCWD, path, flags | O_LARGEFILE, 0));
}

TCS_EXPORT int __openat_2(int dirfd, const char *path, int flags)
{
	return tcs_errno_result(tcs_openat(dirfd, path, flags, 0));
}

TCS_EXPORT int __openat64_2(int dirfd, const char *path, int flags)
{
	return tcs_errno_result(tcs_openat(dirfd, path, flags | O_LARGEFILE, 0));
}

/* ---- stdio ------------------------------------------------------------------ */

/* glibc's stdio reads and writes through internal calls no preload sees,
 * so a device (or a seeded random device) opened with fopen() is a stream
 * of our own over the fd, read and written through the I/O hooks
 * (hooks_io.c). */
static ssize_t tcs_cookie_read(void *c, char *buf, size_t n)
{
	return read((int)(intptr_t)c, buf, n);
}

static ssize_t tcs_cookie_write(void *c, const char *buf, size_t n)
{
	ssize_t r = write((int)(intptr_t)c, buf, n);
	return r < 0 ? 0 : r; /* stdio reports a short write as an error */
}

static int tcs_cookie_close(void *c)
{
	return close((int)(intptr_t)c);
}

/* Whether fopen(path) is ours: a device, or a seeded random device. */
static int tcs_fopen_ours(const char *path)
{
	return tcs_device_lookup(path) >= 0 || (tcs_random_path(path) && tcs_seeded());
}

static FILE *tcs_fopen(const char *path, const char *mode)
{
	int dev = tcs_device_lookup(path);
	int flags = mode[0] == 'r' ? (mode[1] == '+' ? O_RDWR : O_RDONLY) : O_WRONLY;
	for (const char *m = mode; *m; m++)
		if (*m == 'e')
			flags |= O_CLOEXEC;
	long fd = tcs_openat(AT_FDCWD, path, flags, 0);
	if (fd < 0) {
		errno = (int)-fd;
		return NULL;
	}
	cookie_io_functions_t io = { tcs_cookie_read, tcs_cookie_write, NULL, tcs_cookie_close };
	FILE *f = fopencookie((void *)(intptr_t)fd, mode, io);
	if (!f) {
		close((int)fd);
		return NULL;
	}
	/* fileno() must give the device fd: libstdc++'s fstreams read and
	 * write through it (our read/write hooks), not through the FILE. */
	f->_fileno = (int)fd;
	/* Like a serial port (a tty): line-buffered, so each line goes out. */
	if (dev >= 0 && tcs_rt.devices->dev[dev].format == TCS_FORMAT_TEXT)
		setvbuf(f, NULL, _IOLBF, 0);
	return f;
}

/* Everything that is not a device goes to libc's (resolved here when a
 * library's constructor, before ours, opens a configuration file). */
TCS_EXPORT FILE *fopen(const char *path, const char *mode)
{
	if (tcs_fopen_ours(path))
		return tcs_fopen(path, mode);
	return tcs_real()->fopen(path, mode);
}

TCS_EXPORT FILE *fopen64(const char *path, const char *mode)
{
	if (tcs_fopen_ours(path))
		return tcs_fopen(path, mode);
	return tcs_real()->fopen64(path, mode);
}

/* ---- line settings and ioctls ------------------------------------------------------ */

/* A scenario's serial line (a wire) keeps its settings and times its bytes
 * (serial.c); a record device answers like a serial port (devices.c). */
TCS_EXPORT int tcgetattr(int fd, struct termios *t)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->tcgetattr)
		return tcs_errno_result(e.ops->tcgetattr(fd, &e, t));
	return tcs_real()->tcgetattr(fd, t);
}

TCS_EXPORT int tcsetattr(int fd, int when, const struct termios *t)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->tcsetattr)
		return tcs_errno_result(e.ops->tcsetattr(fd, &e, when, t));
	return tcs_real()->tcsetattr(fd, when, t);
}

TCS_EXPORT int tcflush(int fd, int queue)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->tcflush)
		return tcs_errno_result(e.ops->tcflush(fd, &e, queue));
	return tcs_errno_result(tcs_sys3(SYS_ioctl, fd, TCFLSH, queue));
}

TCS_EXPORT int tcdrain(int fd)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->tcdrain)
		return tcs_errno_result(e.ops->tcdrain(fd, &e));
	return tcs_errno_result(tcs_sys3(SYS_ioctl, fd, TCSBRK, 1));
}

TCS_EXPORT int ioctl(int fd, unsigned long request, ...)
{
	va_list ap;
	va_start(ap, request);
	void *arg = va_arg(ap, void *);
	va_end(ap);
	/* What the kernel answers for every fd whatever it is (fs/ioctl.c,
	 * do_vfs_ioctl): the open file's O_NONBLOCK and close-on-exec, which a
	 * served fd keeps on its real fd, where its reads look. (Python's
	 * socket.setblocking and settimeout are FIONBIO.) */
	if (request == FIONBIO || request == FIOCLEX || request == FIONCLEX)
		return tcs_errno_result(tcs_sys3(SYS_ioctl, fd, request, arg));
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->ioctl)
		return tcs_errno_result(e.ops->ioctl(fd, &e, request, arg));
	/* A CAN interface's name or index, asked of any socket. */
	long r = tcs_can_if_ioctl(request, arg);
	return tcs_errno_result(r == 1 ? tcs_sys3(SYS_ioctl, fd, request, arg) : r);
}
