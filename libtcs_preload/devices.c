/* Virtual devices on the preload's side: which fds are devices, and the
 * two requests that keep them in virtual time. A device fd is a real
 * socket whose other end the coordinator holds; before a read or a
 * readiness check the coordinator puts in what is due at the controller's
 * virtual time (or holds the read until it is due), and after a write it
 * takes the records out, stamped with the time they were written. The I/O
 * hooks (hooks_io.c) hand a device's reads and writes to this file whole:
 * from here each makes its one round trip, or none (lazy_writes.c). */
#include <fcntl.h>
#include <sys/socket.h>
#include <sys/uio.h>

#include "journal.h"
#include "devices.h"
#include "lazy_writes.h"
#include "raw_syscall.h"
#include "report.h"
#include "roundtrip.h"
#include "can.h"
#include "i2c.h"
#include "serial.h"
#include "spin.h"
#include "vclock.h"
#include "wait.h"
#include "wire_fds.h"

/* fd -> device handle + 1 (0: not a device). fds beyond the table are
 * never devices: open() moves a device fd below it if it must. */
static int32_t tcs_fd_handle[TCS_DEVICE_FD_MAX];
static uint8_t tcs_fd_kind[TCS_DEVICE_FD_MAX]; /* enum tcs_device_kind, | TCS_FD_STREAM */
static uint8_t tcs_fd_dev[TCS_DEVICE_FD_MAX];  /* the device's index in the table */
#define TCS_FD_STREAM 0x80 /* a stream sensor: records in the fd are due */
static int tcs_open_devices;

int tcs_device_lookup(const char *path)
{
	if (!tcs_active() || !path || path[0] != '/' || !tcs_rt.devices)
		return -1;
	const struct tcs_device_table *t = tcs_rt.devices;
	for (uint32_t i = 0; i < t->count && i < TCS_MAX_DEVICES; i++)
		if (tcs_str_equal(t->dev[i].path, path))
			return (int)i;
	return -1;
}

int tcs_device_handle(int fd)
{
	if (fd < 0 || fd >= TCS_DEVICE_FD_MAX)
		return -1;
	return __atomic_load_n(&tcs_fd_handle[fd], __ATOMIC_RELAXED) - 1;
}

int tcs_device_kind(int fd)
{
	return tcs_device_handle(fd) < 0 ? 0 : tcs_fd_kind[fd] & ~TCS_FD_STREAM;
}

/* The table entry of the device fd is (a device fd only). */
static const struct tcs_device_entry *tcs_device_entry(int fd)
{
	return &tcs_rt.devices->dev[tcs_fd_dev[fd]];
}

/* Whether fd is a stream sensor, whose records in the fd are all due. */
static int tcs_device_streams(int fd)
{
	return tcs_device_handle(fd) >= 0 && (tcs_fd_kind[fd] & TCS_FD_STREAM);
}

int tcs_devices_open(void)
{
	return __atomic_load_n(&tcs_open_devices, __ATOMIC_RELAXED);
}

void tcs_device_forget(int fd)
{
	if (tcs_device_handle(fd) >= 0) {
		tcs_wire_fd_forget(fd);
		__atomic_store_n(&tcs_fd_handle[fd], 0, __ATOMIC_RELAXED);
		__atomic_sub_fetch(&tcs_open_devices, 1, __ATOMIC_RELAXED);
	}
}

void tcs_device_copy(int from, int to)
{
	int h = tcs_device_handle(from);
	if (h < 0 || to < 0 || to >= TCS_DEVICE_FD_MAX)
		return;
	tcs_device_forget(to);
	tcs_fd_kind[to] = tcs_fd_kind[from];
	tcs_fd_dev[to] = tcs_fd_dev[from];
	tcs_wire_fd_copy(from, to);
	__atomic_store_n(&tcs_fd_handle[to], h + 1, __ATOMIC_RELAXED);
	__atomic_add_fetch(&tcs_open_devices, 1, __ATOMIC_RELAXED);
}

long tcs_device_open(int dev, int oflags)
{
	const struct tcs_device_entry *e = &tcs_rt.devices->dev[dev];
	int access = oflags & O_ACCMODE;
	const int wire = e->kind == TCS_DEVICE_SERIAL || e->kind == TCS_DEVICE_I2C || e->kind == TCS_DEVICE_CAN;
	if ((e->kind == TCS_DEVICE_SENSOR && access != O_RDONLY) ||
	    (e->kind == TCS_DEVICE_ACTUATOR && access != O_WRONLY) || (wire && access == 3))
		return -EACCES;
	if (!tcs_wait_enter())
		return -EBUSY;
	struct tcs_msg m = tcs_msg_make(TCS_MSG_DEV_OPEN, 0), w;
	m.arg = dev;
	m.cpu = tcs_charge_point(TCS_MSG_DEV_OPEN);
	m.v = tcs_page_vnow(tcs_rt.page, tcs_page_read_slice(tcs_rt.page), m.cpu);
	m.flags = (uint16_t)((access == O_RDONLY ? TCS_DEV_READ : access == O_WRONLY ? TCS_DEV_WRITE : TCS_DEV_READ | TCS_DEV_WRITE) |
			     ((oflags & O_NONBLOCK) ? TCS_DEV_NONBLOCK : 0));
	int fd;
	tcs_roundtrip(&m, NULL, 0, NULL, &w, &fd);
	tcs_wait_leave();
	if (fd < 0)
		return w.arg < 0 ? w.arg : -EIO;
	if (fd >= TCS_DEVICE_FD_MAX) {
		long low = tcs_sys3(SYS_fcntl, fd, F_DUPFD_CLOEXEC, 3);
		tcs_sys1(SYS_close, fd);
		if (low < 0 || low >= TCS_DEVICE_FD_MAX) {
			if (low >= 0)
				tcs_sys1(SYS_close, low);
			return -EMFILE;
		}
		fd = (int)low;
	}
	if (oflags & O_NONBLOCK)
		tcs_sys3(SYS_fcntl, fd, F_SETFL, O_NONBLOCK);
	if (!(oflags & O_CLOEXEC))
		tcs_sys3(SYS_fcntl, fd, F_SETFD, 0);
	if (wire) {
		struct tcs_wire_fd *wf = tcs_wire_fd_new(fd, e->kind);
		if (!wf) {
			tcs_sys1(SYS_close, fd);
			return -EMFILE;
		}
		if (e->kind == TCS_DEVICE_SERIAL)
			tcs_serial_opened(wf, e->width);
		if (e->kind == TCS_DEVICE_CAN)
			tcs_can_opened(wf);
	}
	tcs_fd_kind[fd] = (uint8_t)(e->kind | (e->kind == TCS_DEVICE_SENSOR && !e->latest ? TCS_FD_STREAM : 0));
	tcs_fd_dev[fd] = (uint8_t)dev;
	__atomic_store_n(&tcs_fd_handle[fd], (int32_t)w.arg + 1, __ATOMIC_RELAXED);
	__atomic_add_fetch(&tcs_open_devices, 1, __ATOMIC_RELAXED);
	tcs_lazy_device_opened((int)w.arg);
	return fd;
}

long tcs_device_sync_held(int handle, int fd, unsigned kind)
{
	long fl = fd >= 0 ? tcs_sys3(SYS_fcntl, fd, F_GETFL, 0) : 0;
	return tcs_device_sync_until(handle, kind, fl > 0 && (fl & O_NONBLOCK), -1);
}

long tcs_device_sync_until(int handle, unsigned kind, int nonblock, int64_t deadline)
{
	struct tcs_clock_page *p = tcs_rt.page;
	int64_t cpu = tcs_charge_point(TCS_MSG_DEV_SYNC);
	struct tcs_msg m = tcs_msg_make(TCS_MSG_DEV_SYNC, 0), w;
	m.kind = (uint16_t)kind;
	m.flags = (uint16_t)(nonblock ? TCS_DEV_NONBLOCK : 0);
	if (deadline >= 0) {
		m.flags |= TCS_DEV_DEADLINE;
		m.deadline = deadline;
	}
	m.arg = handle;
	m.cpu = cpu;
	m.v = tcs_page_vnow(p, tcs_page_read_slice(p), cpu);
	unsigned early = tcs_roundtrip(&m, NULL, 0, NULL, &w, NULL);
	if (early == TCS_EARLY_SIGNAL && w.kind == TCS_WAKE_EARLY)
		return -EINTR;
	return w.arg < 0 ? w.arg : 0;
}

/* Brings the device up to the controller's virtual time (kind: TCS_SYNC_*);
 * fd tells whether it is non-blocking. 0 or -errno. */
static long tcs_device_sync(int handle, int fd, unsigned kind)
{
	if (!tcs_wait_enter())
		return 0; /* (no channel for this thread: said once) */
	long r = tcs_device_sync_held(handle, fd, kind);
	/* In lockstep, a read that found nothing and may not wait is a
	 * spin's (one that got a record ends a spin: tcs_got_record). */
	if (r == -EAGAIN)
		tcs_spin_empty_read(1);
	tcs_wait_leave();
	return r;
}

/* ---- reads and writes ---------------------------------------------------------- */

/* Before reading a device: what is due goes into the fd (or the read
 * waits for it, in virtual time). */
static long tcs_before_read(int fd)
{
	int h = tcs_device_handle(fd);
	if (h < 0)
		return 0;
	if (tcs_device_kind(fd) != TCS_DEVICE_SENSOR)
		return -EBADF; /* write-only, like the file it stands for */
	return tcs_device_sync(h, fd, TCS_SYNC_READ);
}

/* A read of got bytes: a record came, and a spin waiting for it ends. */
static long tcs_got_record(long got)
{
	if (got > 0)
		tcs_spin_waited();
	return got;
}

/* Recording or replaying (journal.h): how much each read took, and whether
 * it asked first, are journalled, so that a replay reads as much, after
 * the same requests, whatever the coordinator had put in its fd by then. */
static long tcs_device_read_live(int fd, void *buf, size_t n);
static long tcs_device_read_journalled(int fd, void *buf, size_t n)
{
	struct tcs_journal_entry e;
	if (!tcs_replaying()) {
		long got = tcs_device_read_live(fd, buf, n);
		tcs_journal_note(TCS_J_READ, 0, tcs_vnow(), got); /* (after the sync it made) */
		return got;
	}
	if (tcs_replay_next(TCS_J_CHARGE, TCS_MSG_DEV_SYNC)) {
		long r = tcs_before_read(fd); /* (it found none in its fd there) */
		if (r < 0)
			return r;
	}
	if (!tcs_replay_take(TCS_J_READ, 0, &e)) /* (the record has another call: departed) */
		return tcs_device_read_live(fd, buf, n);
	tcs_replay_reach(e.value);
	if (e.arg <= 0)
		return e.arg;
	size_t want = (size_t)e.arg < n ? (size_t)e.arg : n;
	long got = tcs_sys6(SYS_recvfrom, fd, buf, want, MSG_DONTWAIT, 0, 0);
	if (got == -EAGAIN)
		got = 0;
	if (got >= 0 && (size_t)got < want) {
		/* The world puts records in as it steps, whenever that is in
		 * real time: what is due by now, asked for. */
		tcs_replay_inner_begin();
		long r = tcs_before_read(fd);
		tcs_replay_inner_end();
		long more = r < 0 ? r : tcs_sys6(SYS_recvfrom, fd, (char *)buf + got, want - (size_t)got, MSG_DONTWAIT, 0, 0);
		got += more > 0 ? more : 0;
	}
	if (got != e.arg)
		tcs_replay_depart(TCS_J_READ, got);
	return tcs_got_record(got);
}

long tcs_device_read(int fd, void *buf, size_t n)
{
	if (tcs_device_kind(fd) == TCS_DEVICE_SERIAL)
		return tcs_serial_read(fd, tcs_device_handle(fd), buf, n);
	if (tcs_device_kind(fd) == TCS_DEVICE_I2C)
		return tcs_i2c_read(fd, tcs_device_handle(fd), buf, n);
	if (tcs_device_kind(fd) == TCS_DEVICE_CAN) {
		struct iovec iov = { buf, n };
		struct msghdr mh = { .msg_iov = &iov, .msg_iovlen = 1 };
		return tcs_can_recvmsg(fd, tcs_device_handle(fd), &mh, 0);
	}
	if (__builtin_expect(tcs_journal_on(), 0))
		return tcs_device_read_journalled(fd, buf, n);
	return tcs_device_read_live(fd, buf, n);
}

static long tcs_device_read_live(int fd, void *buf, size_t n)
{
	/* A stream sensor's records already in the fd were due when they were
	 * put there (at the controller's last wake or sync): they are read
	 * without a round trip, as from a serial port's buffer. Once it is
	 * empty, the sync brings what has come due since, or waits for it. */
	if (n > 0 && tcs_device_streams(fd)) {
		long got = tcs_sys6(SYS_recvfrom, fd, buf, n, MSG_DONTWAIT, 0, 0);
		if (got > 0)
			return tcs_got_record(got);
	}
	long r = tcs_before_read(fd);
	if (r < 0)
		return r;
	return tcs_got_record(tcs_sys3(SYS_read, fd, buf, n));
}

long tcs_device_readv(int fd, const struct iovec *iov, int n)
{
	/* Journalled, into its first buffer only: a short read, as a socket's
	 * readv may be, and one the record has whole. */
	if (tcs_device_kind(fd) == TCS_DEVICE_SERIAL) {
		int i = 0;
		while (i < n && iov[i].iov_len == 0)
			i++;
		return i < n ? tcs_serial_read(fd, tcs_device_handle(fd), iov[i].iov_base, iov[i].iov_len) : 0;
	}
	if (tcs_device_kind(fd) == TCS_DEVICE_CAN) {
		struct msghdr mh = { .msg_iov = (struct iovec *)iov, .msg_iovlen = n > 0 ? (size_t)n : 0 };
		return tcs_can_recvmsg(fd, tcs_device_handle(fd), &mh, 0);
	}
	if (__builtin_expect(tcs_journal_on(), 0)) {
		int i = 0;
		while (i < n && iov[i].iov_len == 0)
			i++;
		return i < n ? tcs_device_read_journalled(fd, iov[i].iov_base, iov[i].iov_len) : 0;
	}
	long r = tcs_before_read(fd);
	if (r < 0)
		return r;
	return tcs_got_record(tcs_sys3(SYS_readv, fd, iov, n));
}

/* After writing device handle h (fd): the coordinator takes the records,
 * stamped with the virtual time of the write; a malformed one fails the
 * write. `last` is the last byte written. */
static long tcs_after_write(int h, int fd, long written, char last)
{
	if (h < 0 || written <= 0 || !tcs_active())
		return written;
	tcs_lazy_note_written(h, tcs_device_entry(fd), written, last);
	long r = tcs_device_sync(h, fd, TCS_SYNC_WRITE);
	return r < 0 && r != -EINTR ? r : written;
}

long tcs_device_write(int fd, const void *buf, size_t n)
{
	int h = tcs_device_handle(fd);
	if (tcs_device_kind(fd) == TCS_DEVICE_SERIAL)
		return tcs_serial_write(fd, h, buf, n);
	if (tcs_device_kind(fd) == TCS_DEVICE_I2C)
		return tcs_i2c_write(fd, h, buf, n);
	if (tcs_device_kind(fd) == TCS_DEVICE_CAN) {
		struct iovec iov = { (void *)buf, n };
		struct msghdr mh = { .msg_iov = &iov, .msg_iovlen = 1 };
		return tcs_can_sendmsg(fd, h, &mh, 0);
	}
	if (tcs_device_kind(fd) == TCS_DEVICE_SENSOR)
		return -EBADF; /* read-only, like the file it stands for */
	int lazy = tcs_active() && tcs_lazy_write_begin(h, tcs_device_entry(fd), buf, n);
	long w = tcs_sys3(SYS_write, fd, buf, n);
	if (lazy && w == (long)n) {
		tcs_lazy_write_done(h, n);
		return w;
	}
	return tcs_after_write(h, fd, w, w > 0 ? ((const char *)buf)[w - 1] : 0);
}

long tcs_device_writev(int fd, const struct iovec *iov, int n)
{
	int h = tcs_device_handle(fd);
	if (tcs_device_kind(fd) == TCS_DEVICE_SERIAL) {
		long done = 0;
		for (int i = 0; i < n; i++) {
			long r = tcs_serial_write(fd, h, iov[i].iov_base, iov[i].iov_len);
			if (r < 0)
				return done > 0 ? done : r;
			done += r;
		}
		return done;
	}
	if (tcs_device_kind(fd) == TCS_DEVICE_CAN) {
		struct msghdr mh = { .msg_iov = (struct iovec *)iov, .msg_iovlen = n > 0 ? (size_t)n : 0 };
		return tcs_can_sendmsg(fd, h, &mh, 0);
	}
	if (tcs_device_kind(fd) == TCS_DEVICE_SENSOR)
		return -EBADF;
	long w = tcs_sys3(SYS_writev, fd, iov, n);
	char last = 0;
	for (long left = w, i = 0; left > 0 && i < n; left -= (long)iov[i].iov_len, i++)
		if ((size_t)left <= iov[i].iov_len)
			last = ((const char *)iov[i].iov_base)[left - 1];
	return tcs_after_write(h, fd, w, last);
}

/* ---- a new child ------------------------------------------------------------ */

/* A new child's device fds are its parent's handles: it opens each device
 * again as a controller of its own and puts the new fd in the old one's
 * place (same number, flags and close-on-exec), as if it had opened it. A
 * device it cannot open again is closed (its reads then fail with EBADF,
 * as they would have). */
void tcs_devices_after_fork(void)
{
	if (tcs_devices_open() == 0)
		return;
	for (int fd = 0; fd < TCS_DEVICE_FD_MAX; fd++) {
		if (tcs_device_handle(fd) < 0)
			continue;
		long fl = tcs_sys3(SYS_fcntl, fd, F_GETFL, 0), fdfl = tcs_sys3(SYS_fcntl, fd, F_GETFD, 0);
		int kind = tcs_fd_kind[fd] & ~TCS_FD_STREAM;
		int oflags = (kind == TCS_DEVICE_SENSOR ? O_RDONLY : kind == TCS_DEVICE_ACTUATOR ? O_WRONLY : O_RDWR) | (fl > 0 && (fl & O_NONBLOCK) ? O_NONBLOCK : 0) |
			     (fdfl > 0 && (fdfl & FD_CLOEXEC) ? O_CLOEXEC : 0);
		tcs_device_forget(fd);
		long fresh = tcs_device_open(tcs_fd_dev[fd], oflags);
		if (fresh < 0) {
			tcs_sys1(SYS_close, fd);
			continue;
		}
		tcs_sys3(SYS_dup3, fresh, fd, (oflags & O_CLOEXEC) ? O_CLOEXEC : 0);
		tcs_device_copy((int)fresh, fd);
		tcs_device_forget((int)fresh);
		tcs_sys1(SYS_close, fresh);
	}
}
