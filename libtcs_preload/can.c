/* A SocketCAN socket's fd (see can.h). What the kernel's CAN_RAW checks
 * before a frame leaves the socket (the address, the frame's size against
 * CAN_RAW_FD_FRAMES, an option's length) is checked here or by the
 * coordinator, which keeps what decides who receives a frame (binding,
 * filters, loopback); what shapes a read (the timestamps asked for) stays
 * here. A frame read is one packet from the fd: a tcs_wire_can_rx and the
 * frame's bytes, put there when its last bit had crossed the bus. */
#include "can.h"

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <linux/net_tstamp.h>
#include <linux/sockios.h>
#include <net/if.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/time.h>

#include "can_ifaces.h"
#include "device_requests.h"
#include "raw_syscall.h"
#include "tcs/wire_protocol.h"
#include "thread_waits.h"
#include "vclock.h"
#include "wire_fds.h"
#include "wire_io.h"

/* The part of struct sockaddr_can that CAN_RAW reads and writes
 * (RAW_MIN_NAMELEN). */
#define TCS_CAN_NAMELEN 8u

/* ---- binding and options --------------------------------------------------- */

static long tcs_can_bind(int fd, int h, const struct sockaddr *addr, uint32_t len)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	struct sockaddr_can a;
	if (!addr || len < TCS_CAN_NAMELEN)
		return -EINVAL;
	memset(&a, 0, sizeof a);
	memcpy(&a, addr, TCS_CAN_NAMELEN);
	if (a.can_family != AF_CAN)
		return -EINVAL;
	int32_t ifindex = a.can_ifindex;
	long r = tcs_wire_send(fd, h, TCS_WIRE_BIND, &ifindex, sizeof ifindex);
	if (r == 0)
		w->can_ifindex = ifindex;
	return r;
}

static long tcs_can_getsockname(int fd, struct sockaddr *addr, uint32_t *len)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	struct sockaddr_can a;
	memset(&a, 0, sizeof a);
	a.can_family = AF_CAN;
	a.can_ifindex = w->can_ifindex;
	memcpy(addr, &a, *len < TCS_CAN_NAMELEN ? *len : TCS_CAN_NAMELEN);
	*len = TCS_CAN_NAMELEN;
	return 0;
}

/* The SOL_SOCKET options a read's cmsgs follow: kept here. 1: not one. */
static long tcs_can_stamp_option(struct tcs_wire_fd *w, int name, const void *value, uint32_t len)
{
	if (name != SO_TIMESTAMP_OLD && name != SO_TIMESTAMPNS_OLD && name != SO_TIMESTAMPING_OLD &&
	    name != SO_RXQ_OVFL)
		return 1;
	int v = 0;
	if (len < sizeof v)
		return -EINVAL;
	memcpy(&v, value, sizeof v);
	if (name == SO_TIMESTAMP_OLD || name == SO_TIMESTAMPNS_OLD) {
		if (v)
			w->can_stamp = (uint8_t)name;
		else if (w->can_stamp == name)
			w->can_stamp = 0;
	} else if (name == SO_TIMESTAMPING_OLD) {
		w->can_timestamping = (uint32_t)v;
	} else {
		w->can_rxq_ovfl = v != 0;
	}
	return 0;
}

static long tcs_can_setsockopt(int fd, int h, int level, int name, const void *value, uint32_t len)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	if (level == SOL_SOCKET) {
		long r = tcs_can_stamp_option(w, name, value, len);
		return r == 1 ? tcs_sys5(SYS_setsockopt, fd, level, name, value, len) : r;
	}
	if (level != SOL_CAN_RAW)
		return -EINVAL;
	if (len > 0 && !value)
		return -EFAULT;
	if (len > CAN_RAW_FILTER_MAX * sizeof(struct can_filter))
		return -EINVAL; /* (no option is longer) */
	char packet[sizeof(struct tcs_wire_canopt) + CAN_RAW_FILTER_MAX * sizeof(struct can_filter)];
	struct tcs_wire_canopt head = { level, name };
	memcpy(packet, &head, sizeof head);
	memcpy(packet + sizeof head, value, len);
	long r = tcs_wire_send(fd, h, TCS_WIRE_CANOPT, packet, sizeof head + len);
	if (r < 0)
		return r;
	int v = 0;
	memcpy(&v, value, len < sizeof v ? len : sizeof v);
	switch (name) {
	case CAN_RAW_FD_FRAMES: w->can_fd_frames = v != 0; break;
	case CAN_RAW_LOOPBACK: w->can_loopback = v != 0; break;
	case CAN_RAW_RECV_OWN_MSGS: w->can_recv_own = v != 0; break;
	case CAN_RAW_JOIN_FILTERS: w->can_join = v != 0; break;
	case CAN_RAW_ERR_FILTER: w->can_err_mask = (uint32_t)v & CAN_ERR_MASK; break;
	default: break;
	}
	return 0;
}

static long tcs_can_int_out(int v, void *value, uint32_t *len)
{
	if (*len < sizeof v)
		return -EINVAL;
	memcpy(value, &v, sizeof v);
	*len = sizeof v;
	return 0;
}

static long tcs_can_getsockopt(int fd, int level, int name, void *value, uint32_t *len)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	if (level == SOL_SOCKET) {
		switch (name) {
		case SO_TYPE: return tcs_can_int_out(SOCK_RAW, value, len);
		case SO_DOMAIN: return tcs_can_int_out(AF_CAN, value, len);
		case SO_PROTOCOL: return tcs_can_int_out(CAN_RAW, value, len);
		case SO_TIMESTAMP_OLD:
		case SO_TIMESTAMPNS_OLD: return tcs_can_int_out(w->can_stamp == name, value, len);
		case SO_TIMESTAMPING_OLD: return tcs_can_int_out((int)w->can_timestamping, value, len);
		case SO_RXQ_OVFL: return tcs_can_int_out(w->can_rxq_ovfl, value, len);
		default: return tcs_sys5(SYS_getsockopt, fd, level, name, value, len);
		}
	}
	if (level != SOL_CAN_RAW)
		return -EOPNOTSUPP;
	switch (name) {
	case CAN_RAW_FD_FRAMES: return tcs_can_int_out(w->can_fd_frames, value, len);
	case CAN_RAW_LOOPBACK: return tcs_can_int_out(w->can_loopback, value, len);
	case CAN_RAW_RECV_OWN_MSGS: return tcs_can_int_out(w->can_recv_own, value, len);
	case CAN_RAW_JOIN_FILTERS: return tcs_can_int_out(w->can_join, value, len);
	case CAN_RAW_ERR_FILTER: return tcs_can_int_out((int)w->can_err_mask, value, len);
	default: return -ENOPROTOOPT; /* (CAN_RAW_FILTER: the filters are the coordinator's) */
	}
}

/* ---- frames ------------------------------------------------------------------ */

/* Appends a cmsg to msg if it has room (MSG_CTRUNC if not); *used grows. */
static void tcs_can_cmsg(struct msghdr *msg, size_t *used, int level, int type, const void *data, size_t len)
{
	if (!msg->msg_control || *used + CMSG_SPACE(len) > msg->msg_controllen) {
		msg->msg_flags |= MSG_CTRUNC;
		return;
	}
	struct cmsghdr *c = (struct cmsghdr *)((char *)msg->msg_control + *used);
	memset(c, 0, CMSG_SPACE(len));
	c->cmsg_level = level;
	c->cmsg_type = type;
	c->cmsg_len = CMSG_LEN(len);
	memcpy(CMSG_DATA(c), data, len);
	*used += CMSG_SPACE(len);
}

/* The arrival time t (virtual) on the controller's CLOCK_REALTIME. */
static int64_t tcs_can_realtime(int64_t t)
{
	return tcs_sleep_clock_origin(CLOCK_REALTIME) + t;
}

/* The cmsgs a read of a frame that arrived at t carries, drops the frames
 * its socket had dropped when it was queued. */
static void tcs_can_cmsgs(const struct tcs_wire_fd *w, struct msghdr *msg, int64_t t, uint32_t drops)
{
	size_t used = 0;
	const int64_t real = tcs_can_realtime(t);
	if (w->can_stamp == SO_TIMESTAMP_OLD) {
		struct timeval tv = { real / TCS_NS_PER_S, (real % TCS_NS_PER_S) / 1000 };
		tcs_can_cmsg(msg, &used, SOL_SOCKET, SCM_TIMESTAMP, &tv, sizeof tv);
	} else if (w->can_stamp == SO_TIMESTAMPNS_OLD) {
		struct timespec ts = { real / TCS_NS_PER_S, real % TCS_NS_PER_S };
		tcs_can_cmsg(msg, &used, SOL_SOCKET, SCM_TIMESTAMPNS, &ts, sizeof ts);
	}
	/* The software stamp is reported with SOF_TIMESTAMPING_SOFTWARE; the
	 * generation flag alone reports none (net/socket.c). */
	if (w->can_timestamping & SOF_TIMESTAMPING_SOFTWARE) {
		struct timespec ts[3];
		memset(ts, 0, sizeof ts);
		ts[0].tv_sec = real / TCS_NS_PER_S;
		ts[0].tv_nsec = real % TCS_NS_PER_S;
		tcs_can_cmsg(msg, &used, SOL_SOCKET, SCM_TIMESTAMPING, ts, sizeof ts);
	}
	/* As the kernel's sock_recv_drops: only once the socket has dropped. */
	if (w->can_rxq_ovfl && drops)
		tcs_can_cmsg(msg, &used, SOL_SOCKET, SO_RXQ_OVFL, &drops, sizeof drops);
	msg->msg_controllen = used;
}

static long tcs_can_recvmsg(int fd, int h, struct msghdr *msg, int flags)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	long fl = tcs_sys3(SYS_fcntl, fd, F_GETFL, 0);
	const int nonblock = (flags & MSG_DONTWAIT) || (fl > 0 && (fl & O_NONBLOCK));
	char buf[sizeof(struct tcs_wire_can_rx) + CANFD_MTU];
	long n;
	for (int synced = 0;; synced = 1) {
		/* What is in the fd arrived by the time it was put there. */
		n = tcs_sys6(SYS_recvfrom, fd, buf, sizeof buf, MSG_DONTWAIT | (flags & MSG_PEEK), 0, 0);
		if (n >= (long)sizeof(struct tcs_wire_can_rx))
			break;
		if (n != -EAGAIN)
			return n < 0 ? n : -EIO;
		if (nonblock && synced)
			return -EAGAIN;
		long r = tcs_wire_sync(fd, h, !nonblock, -1);
		if (r < 0 && r != -EAGAIN)
			return r;
	}
	/* A frame got ends a spin, as a device's record does (spin.h): a clock
	 * read after it is its arrival's time, not a spin's read later. */
	tcs_spin_waited();
	struct tcs_wire_can_rx rx;
	memcpy(&rx, buf, sizeof rx);
	const size_t size = (size_t)n - sizeof rx;
	size_t done = 0;
	for (size_t i = 0; i < msg->msg_iovlen && done < size; i++) {
		size_t k = msg->msg_iov[i].iov_len < size - done ? msg->msg_iov[i].iov_len : size - done;
		memcpy(msg->msg_iov[i].iov_base, buf + sizeof rx + done, k);
		done += k;
	}
	msg->msg_flags = (done < size ? MSG_TRUNC : 0) | ((rx.flags & TCS_CAN_RX_LOCAL) ? MSG_DONTROUTE : 0) |
			 ((rx.flags & TCS_CAN_RX_OWN) ? MSG_CONFIRM : 0);
	if (msg->msg_name) {
		struct sockaddr_can a;
		memset(&a, 0, sizeof a);
		a.can_family = AF_CAN;
		a.can_ifindex = rx.ifindex;
		memcpy(msg->msg_name, &a, msg->msg_namelen < TCS_CAN_NAMELEN ? msg->msg_namelen : TCS_CAN_NAMELEN);
		msg->msg_namelen = TCS_CAN_NAMELEN;
	}
	if (msg->msg_control)
		tcs_can_cmsgs(w, msg, rx.t_ns, rx.drops);
	else
		msg->msg_controllen = 0;
	w->can_last_ns = rx.t_ns;
	return (flags & MSG_TRUNC) ? (long)size : (long)done;
}

static long tcs_can_sendmsg(int fd, int h, const struct msghdr *msg, int flags)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	(void)flags;
	char packet[sizeof(int32_t) + CANFD_MTU];
	int32_t ifindex = 0;
	if (msg->msg_name) {
		struct sockaddr_can a;
		if (msg->msg_namelen < TCS_CAN_NAMELEN)
			return -EINVAL;
		memcpy(&a, msg->msg_name, TCS_CAN_NAMELEN);
		if (a.can_family != AF_CAN)
			return -EINVAL;
		ifindex = a.can_ifindex;
	}
	size_t size = 0;
	for (size_t i = 0; i < msg->msg_iovlen; i++) {
		if (msg->msg_iov[i].iov_len > CANFD_MTU - size)
			return -EINVAL;
		memcpy(packet + sizeof ifindex + size, msg->msg_iov[i].iov_base, msg->msg_iov[i].iov_len);
		size += msg->msg_iov[i].iov_len;
	}
	if (size != CAN_MTU && !(size == CANFD_MTU && w->can_fd_frames))
		return -EINVAL;
	memcpy(packet, &ifindex, sizeof ifindex);
	long r = tcs_wire_send(fd, h, TCS_WIRE_DATA, packet, sizeof ifindex + size);
	return r < 0 ? r : (long)size;
}

static long tcs_can_ioctl(int fd, int h, unsigned long request, void *arg)
{
	struct tcs_wire_fd *w = tcs_wire_fd(fd);
	if (!w)
		return -EBADF;
	if (request == SIOCGSTAMP_OLD || request == SIOCGSTAMPNS_OLD) {
		if (w->can_last_ns < 0)
			return -ENOENT;
		const int64_t real = tcs_can_realtime(w->can_last_ns);
		if (request == SIOCGSTAMP_OLD) {
			struct timeval tv = { real / TCS_NS_PER_S, (real % TCS_NS_PER_S) / 1000 };
			memcpy(arg, &tv, sizeof tv);
		} else {
			struct timespec ts = { real / TCS_NS_PER_S, real % TCS_NS_PER_S };
			memcpy(arg, &ts, sizeof ts);
		}
		return 0;
	}
	if (request == FIONREAD) {
		long r = tcs_wire_sync(fd, h, 0, -1);
		if (r < 0 && r != -EAGAIN)
			return r;
		char buf[sizeof(struct tcs_wire_can_rx) + CANFD_MTU];
		long n = tcs_sys6(SYS_recvfrom, fd, buf, sizeof buf, MSG_DONTWAIT | MSG_PEEK, 0, 0);
		*(int *)arg = n > (long)sizeof(struct tcs_wire_can_rx) ? (int)(n - (long)sizeof(struct tcs_wire_can_rx)) : 0;
		return 0;
	}
	long r = tcs_can_if_ioctl(request, arg);
	return r == 1 ? -ENOTTY : r;
}

/* ---- the kind's operations (fd_table.h) ------------------------------------------ */

/* A new CAN fd's state: unbound, loopback on. */
static long tcs_can_opened(int fd, int handle, unsigned dev)
{
	int slot = tcs_wire_slot_new();
	if (slot < 0)
		return slot;
	struct tcs_fd e = { &tcs_can_ops, handle, dev, (unsigned)slot, 0 };
	struct tcs_wire_fd *w = tcs_wire_of(&e);
	w->can_loopback = 1;
	w->can_last_ns = -1;
	tcs_fd_set(fd, &e);
	return 0;
}

/* read, readv, recv and recvfrom are recvmsg; write, writev, send and
 * sendto sendmsg. */
static long tcs_can_read(int fd, const struct tcs_fd *e, void *buf, size_t n)
{
	struct iovec iov = { buf, n };
	struct msghdr mh = { .msg_iov = &iov, .msg_iovlen = 1 };
	return tcs_can_recvmsg(fd, e->handle, &mh, 0);
}

static long tcs_can_readv(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	struct msghdr mh = { .msg_iov = (struct iovec *)iov, .msg_iovlen = n > 0 ? (size_t)n : 0 };
	return tcs_can_recvmsg(fd, e->handle, &mh, 0);
}

static long tcs_can_write(int fd, const struct tcs_fd *e, const void *buf, size_t n)
{
	struct iovec iov = { (void *)buf, n };
	struct msghdr mh = { .msg_iov = &iov, .msg_iovlen = 1 };
	return tcs_can_sendmsg(fd, e->handle, &mh, 0);
}

static long tcs_can_writev(int fd, const struct tcs_fd *e, const struct iovec *iov, int n)
{
	struct msghdr mh = { .msg_iov = (struct iovec *)iov, .msg_iovlen = n > 0 ? (size_t)n : 0 };
	return tcs_can_sendmsg(fd, e->handle, &mh, 0);
}

static long tcs_can_recvmsg_op(int fd, const struct tcs_fd *e, struct msghdr *msg, int flags)
{
	return tcs_can_recvmsg(fd, e->handle, msg, flags);
}

static long tcs_can_sendmsg_op(int fd, const struct tcs_fd *e, const struct msghdr *msg, int flags)
{
	return tcs_can_sendmsg(fd, e->handle, msg, flags);
}

static long tcs_can_bind_op(int fd, const struct tcs_fd *e, const struct sockaddr *addr, uint32_t len)
{
	return tcs_can_bind(fd, e->handle, addr, len);
}

static long tcs_can_getsockname_op(int fd, const struct tcs_fd *e, struct sockaddr *addr, uint32_t *len)
{
	(void)e;
	return tcs_can_getsockname(fd, addr, len);
}

static long tcs_can_setsockopt_op(int fd, const struct tcs_fd *e, int level, int name, const void *value, uint32_t len)
{
	return tcs_can_setsockopt(fd, e->handle, level, name, value, len);
}

static long tcs_can_getsockopt_op(int fd, const struct tcs_fd *e, int level, int name, void *value, uint32_t *len)
{
	(void)e;
	return tcs_can_getsockopt(fd, level, name, value, len);
}

static long tcs_can_ioctl_op(int fd, const struct tcs_fd *e, unsigned long request, void *arg)
{
	return tcs_can_ioctl(fd, e->handle, request, arg);
}

const struct tcs_fd_ops tcs_can_ops = {
	.kind = TCS_FD_CAN,
	.served = 1,
	.access = 1u << O_RDONLY | 1u << O_WRONLY | 1u << O_RDWR,
	.fork_access = O_RDWR,
	.read = tcs_can_read,
	.readv = tcs_can_readv,
	.write = tcs_can_write,
	.writev = tcs_can_writev,
	.recvmsg = tcs_can_recvmsg_op,
	.sendmsg = tcs_can_sendmsg_op,
	.bind = tcs_can_bind_op,
	.getsockname = tcs_can_getsockname_op,
	.setsockopt = tcs_can_setsockopt_op,
	.getsockopt = tcs_can_getsockopt_op,
	.ioctl = tcs_can_ioctl_op,
	.opened = tcs_can_opened,
	.forget = tcs_wire_forget,
	.copy = tcs_wire_copy,
	.after_fork = tcs_device_after_fork,
};
