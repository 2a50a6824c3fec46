/* A device's requests (device_requests.h). A device fd is a real socket
 * whose other end the coordinator holds: the DEV_OPEN round trip's answer
 * carries it. Before a read or a readiness check the coordinator puts in
 * what is due at the controller's virtual time (or holds the read until it
 * is due), and after a write it takes the records out, stamped with the
 * time they were written: that is DEV_SYNC's. */
#include "device_requests.h"

#include <fcntl.h>

#include "lazy_writes.h"
#include "raw_syscall.h"
#include "roundtrip.h"
#include "spin.h"
#include "vclock.h"
#include "wait.h"

long tcs_device_request_open(unsigned dev, int oflags, int *handle)
{
	int access = oflags & O_ACCMODE;
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
	if (fd >= TCS_FD_MAX) {
		long low = tcs_sys3(SYS_fcntl, fd, F_DUPFD_CLOEXEC, 3);
		tcs_sys1(SYS_close, fd);
		if (low < 0 || low >= TCS_FD_MAX) {
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
	tcs_lazy_device_opened((int)w.arg);
	*handle = (int)w.arg;
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
	for (;;) {
		m.cpu = cpu;
		m.v = tcs_page_vnow(p, tcs_page_read_slice(p), cpu);
		unsigned early = tcs_roundtrip(&m, NULL, 0, NULL, &w, NULL);
		if (early != TCS_EARLY_SIGNAL || w.kind != TCS_WAKE_EARLY)
			return w.arg < 0 ? w.arg : 0;
		/* A handler ran while it waited for its record: the coordinator
		 * ended the wait at the signal's time (so that a wait in the
		 * handler began there); the read goes on, as with SA_RESTART. */
		cpu = tcs_charge_point(TCS_MSG_DEV_SYNC);
		m.seq = 0;
	}
}

long tcs_device_sync(int handle, int fd, unsigned kind)
{
	if (!tcs_wait_enter())
		return 0; /* (no channel for this thread: said once) */
	long r = tcs_device_sync_held(handle, fd, kind);
	/* In lockstep, a read that found nothing and may not wait is a
	 * spin's (one that got a record ends a spin). */
	if (r == -EAGAIN)
		tcs_spin_empty_read(1);
	tcs_wait_leave();
	return r;
}

void tcs_device_after_fork(int fd, const struct tcs_fd *e)
{
	long fl = tcs_sys3(SYS_fcntl, fd, F_GETFL, 0), fdfl = tcs_sys3(SYS_fcntl, fd, F_GETFD, 0);
	int oflags = e->ops->fork_access | (fl > 0 && (fl & O_NONBLOCK) ? O_NONBLOCK : 0) |
		     (fdfl > 0 && (fdfl & FD_CLOEXEC) ? O_CLOEXEC : 0);
	const struct tcs_fd_ops *ops = e->ops;
	unsigned dev = e->dev;
	tcs_fd_forget(fd);
	int handle;
	long fresh = tcs_device_request_open(dev, oflags, &handle);
	if (fresh >= 0) {
		tcs_sys3(SYS_dup3, fresh, fd, (oflags & O_CLOEXEC) ? O_CLOEXEC : 0);
		tcs_sys1(SYS_close, fresh);
		if (ops->opened(fd, handle, dev) == 0)
			return;
	}
	tcs_sys1(SYS_close, fd);
}
