/* An I2C bus's fd (see i2c.h). The arguments are checked here as i2c-dev
 * checks them (how many messages, their lengths) so that what goes to the
 * coordinator is well formed; the coordinator checks it all again. A
 * transfer is a packet (tcs/wire_protocol.h), then a wait for its answer,
 * which the coordinator puts in the fd when the transfer has ended. */
#include "i2c.h"

#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <string.h>
#include <sys/socket.h>

#include "device_requests.h"
#include "raw_syscall.h"
#include "tcs/wire_protocol.h"
#include "thread_waits.h"
#include "wire_fds.h"
#include "wire_io.h"

/* What i2c_funcs() (wires/i2c/smbus.h) says the emulated adapter can do:
 * i2c-algo-bit's functions, without PEC. */
#define TCS_I2C_FUNCS 0x0FFF8017u

/* The answer to the transfer just sent: its head and up to cap bytes. The
 * thread waited for the wire until the transfer's end, so its next clock
 * read is no spin's (spin.h): it reads the end, not a spin's read later. */
static long tcs_i2c_answer(int fd, int h, struct tcs_wire_i2c_reply *head, char *data, size_t cap)
{
	char buf[sizeof *head + TCS_WIRE_PAYLOAD_MAX];
	for (;;) {
		long n = tcs_sys6(SYS_recvfrom, fd, buf, sizeof buf, MSG_DONTWAIT, 0, 0);
		if (n >= (long)sizeof *head) {
			tcs_spin_waited();
			memcpy(head, buf, sizeof *head);
			size_t len = (size_t)n - sizeof *head;
			if (head->len != len || len > cap)
				return -EIO;
			memcpy(data, buf + sizeof *head, len);
			return 0;
		}
		if (n != -EAGAIN)
			return n < 0 ? n : -EIO;
		long r = tcs_wire_sync(fd, h, 1, -1);
		if (r < 0 && r != -EAGAIN)
			return r;
	}
}

/* A combined transfer of n messages (I2C_RDWR's): the result (n) or -errno;
 * the read messages' bytes (and, with I2C_M_RECV_LEN, lengths) filled. */
static long tcs_i2c_transfer(int fd, int h, struct i2c_msg *msgs, uint32_t n)
{
	if (n == 0 || n > I2C_RDWR_IOCTL_MAX_MSGS)
		return -EINVAL;
	char packet[TCS_WIRE_PAYLOAD_MAX];
	size_t at = sizeof n + n * sizeof(struct tcs_wire_i2c_msg);
	memcpy(packet, &n, sizeof n);
	for (uint32_t i = 0; i < n; i++) {
		if (msgs[i].len > 8192)
			return -EINVAL;
		struct tcs_wire_i2c_msg m = { msgs[i].addr, msgs[i].flags, msgs[i].len, 0 };
		memcpy(packet + sizeof n + i * sizeof m, &m, sizeof m);
		/* A write's bytes; a block read's first byte (how many bytes
		 * besides the block it takes: i2c-dev reads it). */
		size_t out = !(m.flags & I2C_M_RD) ? m.len : (m.flags & I2C_M_RECV_LEN) && m.len > 0 ? 1 : 0;
		if (at + out > sizeof packet)
			return -EINVAL; /* (over 4 KiB written in one transfer) */
		memcpy(packet + at, msgs[i].buf, out);
		at += out;
	}
	long r = tcs_wire_send(fd, h, TCS_WIRE_XFER, packet, at);
	if (r < 0)
		return r;
	struct tcs_wire_i2c_reply head;
	char data[TCS_WIRE_PAYLOAD_MAX];
	r = tcs_i2c_answer(fd, h, &head, data, sizeof data);
	if (r < 0)
		return r;
	if (head.result < 0)
		return head.result;
	size_t off = 0;
	for (uint32_t i = 0; i < n; i++) {
		if (!(msgs[i].flags & I2C_M_RD))
			continue;
		uint16_t len;
		if (off + sizeof len > head.len)
			return -EIO;
		memcpy(&len, data + off, sizeof len);
		off += sizeof len;
		if (off + len > head.len)
			return -EIO;
		size_t room = (msgs[i].flags & I2C_M_RECV_LEN) ? I2C_SMBUS_BLOCK_MAX + 2 : msgs[i].len;
		memcpy(msgs[i].buf, data + off, len < room ? len : room);
		if (msgs[i].flags & I2C_M_RECV_LEN)
			msgs[i].len = len;
		off += len;
	}
	return head.result;
}

static long tcs_i2c_smbus(int fd, int h, const struct tcs_wire_fd *w, struct i2c_smbus_ioctl_data *a)
{
	struct tcs_wire_smbus s;
	memset(&s, 0, sizeof s);
	if (w->i2c_addr == 0xffff)
		return -ENXIO;
	s.addr = (uint16_t)(w->i2c_addr | (w->i2c_tenbit ? 0x8000 : 0));
	s.read_write = a->read_write;
	s.command = a->command;
	s.size = a->size;
	/* What the kernel copies in: the union, when the call writes or is
	 * a call of both ways (the whole union is harmless to send). */
	if (a->data)
		memcpy(s.data, a->data, sizeof s.data);
	long r = tcs_wire_send(fd, h, TCS_WIRE_SMBUS, &s, sizeof s);
	if (r < 0)
		return r;
	struct tcs_wire_i2c_reply head;
	char data[sizeof s.data];
	r = tcs_i2c_answer(fd, h, &head, data, sizeof data);
	if (r < 0)
		return r;
	if (head.result < 0)
		return head.result;
	if (a->data && a->read_write == I2C_SMBUS_READ && head.len == sizeof data)
		memcpy(a->data, data, sizeof data);
	else if (a->data && (a->size == I2C_SMBUS_PROC_CALL || a->size == I2C_SMBUS_BLOCK_PROC_CALL) &&
		 head.len == sizeof data)
		memcpy(a->data, data, sizeof data);
	return 0;
}

static long tcs_i2c_ioctl(int fd, int h, unsigned long request, void *arg)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	unsigned long v = (unsigned long)arg;
	switch (request) {
	case I2C_SLAVE:
	case I2C_SLAVE_FORCE:
		if (v > (w->i2c_tenbit ? 0x3ffu : 0x7fu))
			return -EINVAL;
		w->i2c_addr = (uint16_t)v;
		return 0;
	case I2C_TENBIT:
		w->i2c_tenbit = v != 0;
		return 0;
	case I2C_FUNCS:
		*(unsigned long *)arg = TCS_I2C_FUNCS;
		return 0;
	case I2C_PEC:
		return v ? -EINVAL : 0; /* (no PEC: the adapter does not say it can) */
	case I2C_RETRIES:
	case I2C_TIMEOUT:
		return 0;
	case I2C_RDWR: {
		struct i2c_rdwr_ioctl_data *d = (struct i2c_rdwr_ioctl_data *)arg;
		return tcs_i2c_transfer(fd, h, d->msgs, d->nmsgs);
	}
	case I2C_SMBUS:
		return tcs_i2c_smbus(fd, h, w, (struct i2c_smbus_ioctl_data *)arg);
	default:
		return -ENOTTY;
	}
}

static long tcs_i2c_read(int fd, int h, void *buf, size_t n)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	if (w->i2c_addr == 0xffff)
		return -ENXIO; /* (no address set: i2c-dev's client has address 0, which nothing answers) */
	if (n > 8192)
		n = 8192;
	struct i2c_msg m = { w->i2c_addr, (uint16_t)(I2C_M_RD | (w->i2c_tenbit ? I2C_M_TEN : 0)), (uint16_t)n, buf };
	long r = tcs_i2c_transfer(fd, h, &m, 1);
	return r < 0 ? r : (long)n;
}

static long tcs_i2c_write(int fd, int h, const void *buf, size_t n)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	if (w->i2c_addr == 0xffff)
		return -ENXIO;
	if (n > 8192)
		n = 8192;
	struct i2c_msg m = { w->i2c_addr, (uint16_t)(w->i2c_tenbit ? I2C_M_TEN : 0), (uint16_t)n, (uint8_t *)buf };
	long r = tcs_i2c_transfer(fd, h, &m, 1);
	return r < 0 ? r : (long)n;
}

/* ---- the kind's operations (fd_table.h) ------------------------------------------ */

static long tcs_i2c_opened(int fd, int handle, unsigned dev)
{
	int slot = tcs_wire_slot_new();
	if (slot < 0)
		return slot;
	struct tcs_fd e = { &tcs_i2c_ops, handle, dev, (unsigned)slot, 0 };
	tcs_fd_set(fd, &e);
	return 0;
}

static long tcs_i2c_read_op(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	return tcs_i2c_read(fd, e->handle, buf, n);
}

static long tcs_i2c_write_op(int fd, const struct tcs_fd *e, const void *buf, size_t n)
{
	return tcs_i2c_write(fd, e->handle, buf, n);
}

static long tcs_i2c_ioctl_op(int fd, const struct tcs_fd *e, unsigned long request, void *arg)
{
	return tcs_i2c_ioctl(fd, e->handle, request, arg);
}

/* i2c-dev has read and write only: the kernel makes readv and writev one
 * message per buffer. */
const struct tcs_fd_ops tcs_i2c_ops = {
	.kind = TCS_FD_I2C,
	.served = 1,
	.access = 1u << O_RDONLY | 1u << O_WRONLY | 1u << O_RDWR,
	.fork_access = O_RDWR,
	.read = tcs_i2c_read_op,
	.readv = tcs_fd_readv_by_reads,
	.write = tcs_i2c_write_op,
	.writev = tcs_fd_writev_by_writes,
	.ioctl = tcs_i2c_ioctl_op,
	.opened = tcs_i2c_opened,
	.forget = tcs_wire_forget,
	.copy = tcs_wire_copy,
	.after_fork = tcs_device_after_fork,
};
