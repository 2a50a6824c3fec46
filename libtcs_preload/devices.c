/* Record devices on the preload's side (devices.h): a sensor's reads and
 * an actuator's writes in virtual time, each with the one round trip it
 * needs (device_requests.c), or none: a stream sensor's records already in
 * its fd, an actuator's writes in lockstep (lazy_writes.c). Recording or
 * replaying, a read is journalled. To termios calls and ioctls a device
 * answers like a serial port in raw mode, 8N1, 115200 baud, and accepts
 * any new settings: programs written for /dev/ttyUSB0 configure the line
 * before they use it. */
#include "devices.h"

#include <fcntl.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <termios.h>

#include "device_requests.h"
#include "lazy_writes.h"
#include "raw_syscall.h"
#include "replay.h"
#include "spin.h"
#include "vclock.h"

#define TCS_FD_STREAM 0x1 /* (the entry's flags) a stream sensor: records in the fd are due */

/* The device table's entry of a device fd. */
static const struct tcs_device_entry *tcs_device_entry(const struct tcs_fd *e)
{
	return &tcs_rt.devices->dev[e->dev];
}

static long tcs_device_opened(int fd, int handle, unsigned dev, const struct tcs_fd_ops *ops)
{
	const struct tcs_device_entry *d = &tcs_rt.devices->dev[dev];
	struct tcs_fd e = { ops, handle, dev, 0, ops == &tcs_sensor_ops && !d->latest ? TCS_FD_STREAM : 0 };
	tcs_fd_set(fd, &e);
	return 0;
}

static long tcs_sensor_opened(int fd, int handle, unsigned dev)
{
	return tcs_device_opened(fd, handle, dev, &tcs_sensor_ops);
}

static long tcs_actuator_opened(int fd, int handle, unsigned dev)
{
	return tcs_device_opened(fd, handle, dev, &tcs_actuator_ops);
}

/* ---- reads and writes ---------------------------------------------------------- */

/* Before reading a device: what is due goes into the fd (or the read
 * waits for it, in virtual time). */
static long tcs_before_read(int fd, const struct tcs_fd *e)
{
	return tcs_device_sync(e->handle, fd, TCS_SYNC_READ);
}

/* A read of got bytes: a record came, and a spin waiting for it ends. */
static long tcs_got_record(long got)
{
	if (got > 0)
		tcs_spin_waited();
	return got;
}

/* Recording or replaying (journal_write.h): how much each read took, and whether
 * it asked first, are journalled, so that a replay reads as much, after
 * the same requests, whatever the coordinator had put in its fd by then. */
static long tcs_device_read_live(int fd, const struct tcs_fd *e, void *buf, size_t n);
static long tcs_device_read_journalled(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	struct tcs_journal_entry j;
	if (!tcs_replaying()) {
		long got = tcs_device_read_live(fd, e, buf, n);
		tcs_journal_note(TCS_J_READ, 0, tcs_vnow(), got); /* (after the sync it made) */
		return got;
	}
	if (tcs_replay_next(TCS_J_CHARGE, TCS_MSG_DEV_SYNC)) {
		long r = tcs_before_read(fd, e); /* (it found none in its fd there) */
		if (r < 0)
			return r;
	}
	if (!tcs_replay_take(TCS_J_READ, 0, &j)) /* (the record has another call: departed) */
		return tcs_device_read_live(fd, e, buf, n);
	tcs_replay_reach(j.value);
	if (j.arg <= 0)
		return j.arg;
	size_t want = (size_t)j.arg < n ? (size_t)j.arg : n;
	long got = tcs_sys6(SYS_recvfrom, fd, buf, want, MSG_DONTWAIT, 0, 0);
	if (got == -EAGAIN)
		got = 0;
	if (got >= 0 && (size_t)got < want) {
		/* The world puts records in as it steps, whenever that is in
		 * real time: what is due by now, asked for. */
		tcs_replay_inner_begin();
		long r = tcs_before_read(fd, e);
		tcs_replay_inner_end();
		long more = r < 0 ? r : tcs_sys6(SYS_recvfrom, fd, (char *)buf + got, want - (size_t)got, MSG_DONTWAIT, 0, 0);
		got += more > 0 ? more : 0;
	}
	if (got != j.arg)
		tcs_replay_depart(TCS_J_READ, got);
	return tcs_got_record(got);
}

static long tcs_sensor_read(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	if (__builtin_expect(tcs_journal_on(), 0))
		return tcs_device_read_journalled(fd, e, buf, n);
	return tcs_device_read_live(fd, e, buf, n);
}

static long tcs_device_read_live(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	/* A stream sensor's records already in the fd were due when they were
	 * put there (at the controller's last wake or sync): they are read
	 * without a round trip, as from a serial port's buffer. Once it is
	 * empty, the sync brings what has come due since, or waits for it. */
	if (n > 0 && (e->flags & TCS_FD_STREAM)) {
		long got = tcs_sys6(SYS_recvfrom, fd, buf, n, MSG_DONTWAIT, 0, 0);
		if (got > 0)
			return tcs_got_record(got);
	}
	long r = tcs_before_read(fd, e);
	if (r < 0)
		return r;
	return tcs_got_record(tcs_sys3(SYS_read, fd, buf, n));
}

static long tcs_sensor_readv(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	/* Journalled, into its first buffer only: a short read, as a socket's
	 * readv may be, and one the record has whole. */
	if (__builtin_expect(tcs_journal_on(), 0)) {
		int i = 0;
		while (i < n && iov[i].iov_len == 0)
			i++;
		return i < n ? tcs_device_read_journalled(fd, e, iov[i].iov_base, iov[i].iov_len) : 0;
	}
	long r = tcs_before_read(fd, e);
	if (r < 0)
		return r;
	return tcs_got_record(tcs_sys3(SYS_readv, fd, iov, n));
}

/* After writing device handle h (fd): the coordinator takes the records,
 * stamped with the virtual time of the write; a malformed one fails the
 * write. `last` is the last byte written. */
static long tcs_after_write(int h, int fd, const struct tcs_fd *e, long written, char last)
{
	if (written <= 0 || !tcs_active())
		return written;
	tcs_lazy_note_written(h, tcs_device_entry(e), written, last);
	long r = tcs_device_sync(h, fd, TCS_SYNC_WRITE);
	return r < 0 && r != -EINTR ? r : written;
}

static long tcs_actuator_write(int fd, const struct tcs_fd *e, const void *buf, size_t n)
{
	int h = e->handle;
	int lazy = tcs_active() && tcs_lazy_write_begin(h, tcs_device_entry(e), buf, n);
	long w = tcs_sys3(SYS_write, fd, buf, n);
	if (lazy && w == (long)n) {
		tcs_lazy_write_done(h, n);
		return w;
	}
	return tcs_after_write(h, fd, e, w, w > 0 ? ((const char *)buf)[w - 1] : 0);
}

static long tcs_actuator_writev(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	long w = tcs_sys3(SYS_writev, fd, iov, n);
	char last = 0;
	for (long left = w, i = 0; left > 0 && i < n; left -= (long)iov[i].iov_len, i++)
		if ((size_t)left <= iov[i].iov_len)
			last = ((const char *)iov[i].iov_base)[left - 1];
	return tcs_after_write(e->handle, fd, e, w, last);
}

/* A sensor is read-only, an actuator write-only, like the files they
 * stand for. */
static long tcs_not_writable(int fd, const struct tcs_fd *e, const void *buf, size_t n)
{
	(void)fd, (void)e, (void)buf, (void)n;
	return -EBADF;
}

static long tcs_not_writable_v(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	(void)fd, (void)e, (void)iov, (void)n;
	return -EBADF;
}

static long tcs_not_readable(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	(void)fd, (void)e, (void)buf, (void)n;
	return -EBADF;
}

static long tcs_not_readable_v(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	(void)fd, (void)e, (void)iov, (void)n;
	return -EBADF;
}

/* ---- a serial port's line settings, as a text device answers them ------------ */

static long tcs_device_tcgetattr(int fd, const struct tcs_fd *e, struct termios *t)
{
	(void)fd, (void)e;
	memset(t, 0, sizeof *t);
	t->c_cflag = CS8 | CREAD | CLOCAL | B115200;
	t->c_ispeed = B115200;
	t->c_ospeed = B115200;
	return 0;
}

static long tcs_device_tcsetattr(int fd, const struct tcs_fd *e, int when, const struct termios *t)
{
	(void)fd, (void)e, (void)when, (void)t;
	return 0;
}

static long tcs_device_tcflush(int fd, const struct tcs_fd *e, int queue)
{
	(void)fd, (void)e, (void)queue;
	return 0;
}

static long tcs_device_tcdrain(int fd, const struct tcs_fd *e)
{
	(void)fd, (void)e;
	return 0;
}

/* The kernel's struct termios, as TCGETS fills it (not glibc's). */
struct tcs_kernel_termios {
	unsigned int c_iflag, c_oflag, c_cflag, c_lflag;
	unsigned char c_line;
	unsigned char c_cc[19];
};

static long tcs_device_ioctl(int fd, const struct tcs_fd *e, unsigned long request, void *arg)
{
	(void)e;
	switch (request) {
	case TCGETS: {
		struct tcs_kernel_termios *t = (struct tcs_kernel_termios *)arg;
		memset(t, 0, sizeof *t);
		t->c_cflag = CS8 | CREAD | CLOCAL | B115200;
		return 0;
	}
	case TIOCMGET:
		*(int *)arg = TIOCM_DTR | TIOCM_RTS | TIOCM_CTS | TIOCM_DSR;
		return 0;
	case TCSETS:
	case TCSETSW:
	case TCSETSF:
	case TCFLSH:
	case TCSBRK:
	case TCXONC:
	case TIOCMSET:
	case TIOCMBIS:
	case TIOCMBIC:
	case TIOCEXCL:
	case TIOCNXCL:
		return 0;
	default: /* FIONREAD and the socket's own work as they are */
		return tcs_sys3(SYS_ioctl, fd, request, arg);
	}
}

/* ---- the two kinds -------------------------------------------------------------- */

const struct tcs_fd_ops tcs_sensor_ops = {
	.kind = TCS_FD_SENSOR,
	.served = 1,
	.access = 1u << O_RDONLY,
	.fork_access = O_RDONLY,
	.read = tcs_sensor_read,
	.readv = tcs_sensor_readv,
	.write = tcs_not_writable,
	.writev = tcs_not_writable_v,
	.ioctl = tcs_device_ioctl,
	.tcgetattr = tcs_device_tcgetattr,
	.tcsetattr = tcs_device_tcsetattr,
	.tcflush = tcs_device_tcflush,
	.tcdrain = tcs_device_tcdrain,
	.opened = tcs_sensor_opened,
	.after_fork = tcs_device_after_fork,
};

const struct tcs_fd_ops tcs_actuator_ops = {
	.kind = TCS_FD_ACTUATOR,
	.served = 1,
	.access = 1u << O_WRONLY,
	.fork_access = O_WRONLY,
	.read = tcs_not_readable,
	.readv = tcs_not_readable_v,
	.write = tcs_actuator_write,
	.writev = tcs_actuator_writev,
	.ioctl = tcs_device_ioctl,
	.tcgetattr = tcs_device_tcgetattr,
	.tcsetattr = tcs_device_tcsetattr,
	.tcflush = tcs_device_tcflush,
	.tcdrain = tcs_device_tcdrain,
	.opened = tcs_actuator_opened,
	.after_fork = tcs_device_after_fork,
};
