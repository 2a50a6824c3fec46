/* A serial line's fd (see serial.h). Reads follow the tty layer in raw
 * (non-canonical) mode: O_NONBLOCK reads fail with EAGAIN when nothing has
 * arrived; with VMIN 0 and VTIME 0 they return 0; VMIN 0 and VTIME t wait
 * t tenths of a second for a first byte; VMIN n waits for n bytes (or as
 * many as asked), with VTIME t then ending the wait t tenths after the
 * last byte. Canonical mode, echo and the other flags are kept as set and
 * have no effect: a program driving a servo bus sets raw mode. */
#include "serial.h"

#include <fcntl.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <termios.h>

#include "device_requests.h"
#include "raw_syscall.h"
#include "spin.h"
#include "tcs/protocol.h"
#include "tcs/wire_protocol.h"
#include "vclock.h"
#include "wait.h"
#include "wire_fds.h"
#include "wire_io.h"

/* The kernel's struct termios and termios2, as TCGETS and TCGETS2 fill
 * them (not glibc's, whose c_cc is longer). */
struct tcs_kernel_termios {
	unsigned int c_iflag, c_oflag, c_cflag, c_lflag;
	unsigned char c_line;
	unsigned char c_cc[19];
};
struct tcs_kernel_termios2 {
	unsigned int c_iflag, c_oflag, c_cflag, c_lflag;
	unsigned char c_line;
	unsigned char c_cc[19];
	unsigned int c_ispeed, c_ospeed;
};
#define TCS_TCGETS2 _IOR('T', 0x2A, struct tcs_kernel_termios2)
#define TCS_TCSETS2 _IOW('T', 0x2B, struct tcs_kernel_termios2)
#define TCS_TCSETSW2 _IOW('T', 0x2C, struct tcs_kernel_termios2)
#define TCS_TCSETSF2 _IOW('T', 0x2D, struct tcs_kernel_termios2)
#define TCS_BOTHER 0010000
#define TCS_CBAUD 0010017

static const struct {
	speed_t code;
	uint32_t baud;
} tcs_speeds[] = {
	{ B50, 50 }, { B75, 75 }, { B110, 110 }, { B134, 134 }, { B150, 150 }, { B200, 200 }, { B300, 300 },
	{ B600, 600 }, { B1200, 1200 }, { B1800, 1800 }, { B2400, 2400 }, { B4800, 4800 }, { B9600, 9600 },
	{ B19200, 19200 }, { B38400, 38400 }, { B57600, 57600 }, { B115200, 115200 }, { B230400, 230400 },
	{ B460800, 460800 }, { B500000, 500000 }, { B576000, 576000 }, { B921600, 921600 },
	{ B1000000, 1000000 }, { B1152000, 1152000 }, { B1500000, 1500000 }, { B2000000, 2000000 },
	{ B2500000, 2500000 }, { B3000000, 3000000 }, { B3500000, 3500000 }, { B4000000, 4000000 },
};

/* The rate of a speed code; 0 for B0 or an unknown code. */
static uint32_t tcs_baud_of(speed_t code)
{
	for (size_t i = 0; i < sizeof tcs_speeds / sizeof tcs_speeds[0]; i++)
		if (tcs_speeds[i].code == code)
			return tcs_speeds[i].baud;
	return 0;
}

static speed_t tcs_code_of(uint32_t baud)
{
	for (size_t i = 0; i < sizeof tcs_speeds / sizeof tcs_speeds[0]; i++)
		if (tcs_speeds[i].baud == baud)
			return tcs_speeds[i].code;
	return TCS_BOTHER;
}

/* Start bit, data bits, parity, stop bits. */
static uint32_t tcs_frame_bits(tcflag_t cflag)
{
	static const uint32_t data[] = { 5, 6, 7, 8 };
	return 1 + data[(cflag & CSIZE) >> 4] + ((cflag & PARENB) ? 1 : 0) + ((cflag & CSTOPB) ? 2 : 1);
}

/* A new serial fd's line: raw, 8N1, VMIN 1, at baud. */
static void tcs_serial_line_init(struct tcs_wire_fd *w, uint32_t baud)
{
	memset(&w->tio, 0, sizeof w->tio);
	speed_t code = tcs_code_of(baud);
	w->tio.c_cflag = CS8 | CREAD | CLOCAL | (code & TCS_CBAUD);
	w->tio.c_cc[VMIN] = 1;
	w->tio.c_ispeed = w->tio.c_ospeed = code;
	w->baud = baud;
	/* DTR and RTS raised, as the tty layer does at the open of a line with
	 * a rate; CTS and DSR: an adapter whose other end is ready. */
	w->modem = TIOCM_DTR | TIOCM_RTS | TIOCM_CTS | TIOCM_DSR;
}

/* The lines a program drives: DTR and RTS (tty_tiocmset also takes OUT1,
 * OUT2 and LOOP, which a USB adapter does not have). */
#define TCS_TIOCM_OUT (TIOCM_DTR | TIOCM_RTS)

/* The line's new rate and frame to the coordinator (when they changed). */
static long tcs_serial_line(int fd, int h, struct tcs_wire_fd *w, uint32_t baud, tcflag_t cflag)
{
	uint32_t old_bits = tcs_frame_bits(w->tio.c_cflag);
	struct tcs_wire_line line = { baud, tcs_frame_bits(cflag) };
	if (baud == w->baud && line.bits_per_byte == old_bits)
		return 0;
	if (baud == 0)
		return -EINVAL; /* (B0 hangs up a modem line; a servo bus has none) */
	w->baud = baud;
	return tcs_wire_send(fd, h, TCS_WIRE_LINE, &line, sizeof line);
}

static long tcs_serial_getattr(int fd, struct termios *t)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	*t = w->tio;
	return 0;
}

static long tcs_serial_setattr(int fd, int h, const struct termios *t)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	long r = tcs_serial_line(fd, h, w, tcs_baud_of(t->c_cflag & TCS_CBAUD), t->c_cflag);
	if (r < 0)
		return r;
	w->tio = *t;
	return 0;
}

static long tcs_serial_flush(int fd, int h, int queue)
{
	if (queue != TCIFLUSH && queue != TCIOFLUSH)
		return queue == TCOFLUSH ? 0 : -EINVAL; /* (what is on the wire goes on) */
	long r = tcs_wire_sync(fd, h, 0, -1);
	if (r < 0 && r != -EAGAIN)
		return r;
	char buf[256];
	while (tcs_sys6(SYS_recvfrom, fd, buf, sizeof buf, MSG_DONTWAIT, 0, 0) > 0)
		;
	return 0;
}

static long tcs_serial_drain(int fd, int h)
{
	if (!tcs_wait_enter())
		return 0;
	long r = tcs_device_sync_until(h, TCS_SYNC_DRAIN, 0, -1);
	tcs_wait_leave();
	tcs_spin_waited(); /* (it waited for the wire: no spin, spin.h) */
	return r;
}

/* A read's end. One that got bytes ends a spin, as a device's record does,
 * and one that waited for them (VMIN, VTIME) made a wait: either way the
 * thread's next clock read is no spin's (spin.h), so that a clock read
 * after a reply is its arrival's time, not a spin's read later. */
static long tcs_serial_read_end(long got, int waited)
{
	if (got > 0 || waited)
		tcs_spin_waited();
	return got;
}

static long tcs_serial_read(int fd, int h, void *buf, size_t n)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	if (n == 0)
		return 0;
	long fl = tcs_sys3(SYS_fcntl, fd, F_GETFL, 0);
	const int nonblock = fl > 0 && (fl & O_NONBLOCK);
	const size_t vmin = w->tio.c_cc[VMIN], vtime = w->tio.c_cc[VTIME];
	const int64_t tenths = (int64_t)vtime * 100 * TCS_NS_PER_MS;
	const size_t want = vmin < n ? vmin : n;
	size_t got = 0;
	int waited = 0;
	for (int first = 1;; first = 0) {
		/* What is in the fd arrived by the time it was put there. */
		long k = tcs_sys6(SYS_recvfrom, fd, (char *)buf + got, n - got, MSG_DONTWAIT, 0, 0);
		if (k > 0)
			got += (size_t)k;
		if (got > 0 && got >= want)
			return tcs_serial_read_end((long)got, waited);
		if (!first && (nonblock || vmin == 0 || (vtime > 0 && k <= 0)))
			return got > 0 || !nonblock ? tcs_serial_read_end((long)got, waited) : -EAGAIN;
		long r;
		if (nonblock || (vmin == 0 && vtime == 0)) {
			r = tcs_wire_sync(fd, h, 0, -1);
		} else {
			waited = 1;
			r = tcs_wire_sync(fd, h, 1, vmin == 0 || (vtime > 0 && got > 0) ? tcs_vnow() + tenths : -1);
		}
		if (r < 0 && r != -EAGAIN)
			return got > 0 ? tcs_serial_read_end((long)got, waited) : r;
	}
}

static long tcs_serial_write(int fd, int h, const void *buf, size_t n)
{
	size_t done = 0;
	while (done < n) {
		size_t k = n - done < TCS_WIRE_PAYLOAD_MAX ? n - done : TCS_WIRE_PAYLOAD_MAX;
		long r = tcs_wire_send(fd, h, TCS_WIRE_DATA, (const char *)buf + done, k);
		if (r < 0)
			return done > 0 ? (long)done : r;
		done += k;
	}
	return (long)n;
}

static void tcs_to_kernel(const struct termios *t, struct tcs_kernel_termios2 *k)
{
	memset(k, 0, sizeof *k);
	k->c_iflag = t->c_iflag;
	k->c_oflag = t->c_oflag;
	k->c_cflag = t->c_cflag;
	k->c_lflag = t->c_lflag;
	k->c_line = t->c_line;
	memcpy(k->c_cc, t->c_cc, sizeof k->c_cc);
}

static void tcs_from_kernel(const struct tcs_kernel_termios2 *k, struct termios *t)
{
	memset(t, 0, sizeof *t);
	t->c_iflag = k->c_iflag;
	t->c_oflag = k->c_oflag;
	t->c_cflag = k->c_cflag;
	t->c_lflag = k->c_lflag;
	t->c_line = k->c_line;
	memcpy(t->c_cc, k->c_cc, sizeof k->c_cc);
	t->c_ispeed = t->c_ospeed = t->c_cflag & TCS_CBAUD;
}

static long tcs_serial_ioctl(int fd, int h, unsigned long request, void *arg)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	struct tcs_kernel_termios2 k;
	struct termios t;
	switch (request) {
	case TCGETS:
	case TCS_TCGETS2:
		tcs_to_kernel(&w->tio, &k);
		if ((w->tio.c_cflag & TCS_CBAUD) == TCS_BOTHER || request == TCS_TCGETS2)
			k.c_ispeed = k.c_ospeed = w->baud;
		memcpy(arg, &k, request == TCGETS ? sizeof(struct tcs_kernel_termios) : sizeof k);
		return 0;
	case TCSETS:
	case TCSETSW:
	case TCSETSF:
	case TCS_TCSETS2:
	case TCS_TCSETSW2:
	case TCS_TCSETSF2: {
		const int two = request == TCS_TCSETS2 || request == TCS_TCSETSW2 || request == TCS_TCSETSF2;
		memset(&k, 0, sizeof k);
		memcpy(&k, arg, two ? sizeof k : sizeof(struct tcs_kernel_termios));
		tcs_from_kernel(&k, &t);
		uint32_t baud = (k.c_cflag & TCS_CBAUD) == TCS_BOTHER && two ? k.c_ospeed : tcs_baud_of(k.c_cflag & TCS_CBAUD);
		if (request == TCSETSW || request == TCS_TCSETSW2 || request == TCSETSF || request == TCS_TCSETSF2) {
			long r = tcs_serial_drain(fd, h);
			if (r < 0)
				return r;
		}
		if (request == TCSETSF || request == TCS_TCSETSF2)
			(void)tcs_serial_flush(fd, h, TCIFLUSH);
		long r = tcs_serial_line(fd, h, w, baud, k.c_cflag);
		if (r < 0)
			return r;
		w->tio = t;
		return 0;
	}
	case TCFLSH:
		return tcs_serial_flush(fd, h, (int)(intptr_t)arg);
	case TCSBRK:
		return (intptr_t)arg ? tcs_serial_drain(fd, h) : 0;
	case FIONREAD: {
		long r = tcs_wire_sync(fd, h, 0, -1);
		if (r < 0 && r != -EAGAIN)
			return r;
		return tcs_sys3(SYS_ioctl, fd, FIONREAD, arg);
	}
	case TIOCOUTQ:
		*(int *)arg = 0;
		return 0;
	case TIOCMGET:
		*(int *)arg = (int)w->modem;
		return 0;
	case TIOCMSET:
		w->modem = (w->modem & ~(uint32_t)TCS_TIOCM_OUT) | (*(const int *)arg & TCS_TIOCM_OUT);
		return 0;
	case TIOCMBIS:
		w->modem |= *(const int *)arg & TCS_TIOCM_OUT;
		return 0;
	case TIOCMBIC:
		w->modem &= ~(uint32_t)(*(const int *)arg & TCS_TIOCM_OUT);
		return 0;
	case TIOCGSERIAL:
		memset(arg, 0, 72); /* struct serial_struct: nothing to say */
		return 0;
	case TIOCSSERIAL:
	case TCXONC:
	case TIOCEXCL:
	case TIOCNXCL:
	case TIOCSBRK:
	case TIOCCBRK:
		return 0;
	default:
		return -ENOTTY;
	}
}

/* ---- the kind's operations (fd_table.h) ------------------------------------------ */

static long tcs_serial_opened(int fd, int handle, unsigned dev)
{
	int slot = tcs_wire_slot_new();
	if (slot < 0)
		return slot;
	struct tcs_fd e = { &tcs_serial_ops, handle, dev, (unsigned)slot, 0 };
	tcs_serial_line_init(tcs_wire_of(&e), tcs_rt.devices->dev[dev].width);
	tcs_fd_set(fd, &e);
	return 0;
}

static long tcs_serial_read_op(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	return tcs_serial_read(fd, e->handle, buf, n);
}

/* Into its first buffer only: a short read, as a tty's readv may be. */
static long tcs_serial_readv_op(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	int i = 0;
	while (i < n && iov[i].iov_len == 0)
		i++;
	return i < n ? tcs_serial_read(fd, e->handle, iov[i].iov_base, iov[i].iov_len) : 0;
}

static long tcs_serial_write_op(int fd, const struct tcs_fd *e, const void *buf, size_t n)
{
	return tcs_serial_write(fd, e->handle, buf, n);
}

static long tcs_serial_ioctl_op(int fd, const struct tcs_fd *e, unsigned long request, void *arg)
{
	return tcs_serial_ioctl(fd, e->handle, request, arg);
}

static long tcs_serial_tcgetattr(int fd, const struct tcs_fd *e, struct termios *t)
{
	(void)e;
	return tcs_serial_getattr(fd, t);
}

static long tcs_serial_tcsetattr(int fd, const struct tcs_fd *e, int when, const struct termios *t)
{
	if (when == TCSADRAIN || when == TCSAFLUSH) {
		long r = tcs_serial_drain(fd, e->handle);
		if (r < 0)
			return r;
	}
	if (when == TCSAFLUSH)
		(void)tcs_serial_flush(fd, e->handle, TCIFLUSH);
	return tcs_serial_setattr(fd, e->handle, t);
}

static long tcs_serial_tcflush(int fd, const struct tcs_fd *e, int queue)
{
	return tcs_serial_flush(fd, e->handle, queue);
}

static long tcs_serial_tcdrain(int fd, const struct tcs_fd *e)
{
	return tcs_serial_drain(fd, e->handle);
}

const struct tcs_fd_ops tcs_serial_ops = {
	.kind = TCS_FD_SERIAL,
	.served = 1,
	.access = 1u << O_RDONLY | 1u << O_WRONLY | 1u << O_RDWR,
	.fork_access = O_RDWR,
	.read = tcs_serial_read_op,
	.readv = tcs_serial_readv_op,
	.write = tcs_serial_write_op,
	.writev = tcs_fd_writev_by_writes,
	.ioctl = tcs_serial_ioctl_op,
	.tcgetattr = tcs_serial_tcgetattr,
	.tcsetattr = tcs_serial_tcsetattr,
	.tcflush = tcs_serial_tcflush,
	.tcdrain = tcs_serial_tcdrain,
	.opened = tcs_serial_opened,
	.forget = tcs_wire_forget,
	.copy = tcs_wire_copy,
	.after_fork = tcs_device_after_fork,
};
