/* Socket hooks: socket(PF_CAN, SOCK_RAW, CAN_RAW), when the scenario has
 * CAN interfaces, opens its CAN bus as a wire the coordinator serves
 * (can.c); bind, the socket options, getsockname, send* and recv* of an fd
 * tcs serves are its entry's operations (fd_table.h). The interfaces'
 * names and indexes are answered from the device table (if_nametoindex,
 * if_indextoname: glibc's ask the kernel through calls no preload sees;
 * the ioctls are hooks_device.c's). Every other socket, and every other
 * call, goes straight to the kernel: `ip link` and netlink do not see the
 * interfaces. */
#include <fcntl.h>
#include <linux/can.h>
#include <net/if.h>
#include <string.h>
#include <sys/socket.h>

#include "can_ifaces.h"
#include "device_open.h"
#include "fd_table.h"
#include "raw_syscall.h"
#include "real.h"

TCS_EXPORT int socket(int domain, int type, int protocol)
{
	if (domain == PF_CAN && (type & 0xf) == SOCK_RAW && protocol == CAN_RAW && tcs_active()) {
		int dev = tcs_can_first_device();
		if (dev >= 0)
			return tcs_errno_result(tcs_device_open(dev, O_RDWR | ((type & SOCK_NONBLOCK) ? O_NONBLOCK : 0) |
									     ((type & SOCK_CLOEXEC) ? O_CLOEXEC : 0)));
	}
	return tcs_errno_result(tcs_sys3(SYS_socket, domain, type, protocol));
}

TCS_EXPORT int bind(int fd, const struct sockaddr *addr, socklen_t len)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->bind)
		return tcs_errno_result(e.ops->bind(fd, &e, addr, len));
	return tcs_errno_result(tcs_sys3(SYS_bind, fd, addr, len));
}

TCS_EXPORT int getsockname(int fd, struct sockaddr *addr, socklen_t *len)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->getsockname)
		return tcs_errno_result(e.ops->getsockname(fd, &e, addr, len));
	return tcs_errno_result(tcs_sys3(SYS_getsockname, fd, addr, len));
}

TCS_EXPORT int setsockopt(int fd, int level, int name, const void *value, socklen_t len)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->setsockopt)
		return tcs_errno_result(e.ops->setsockopt(fd, &e, level, name, value, len));
	return tcs_errno_result(tcs_sys5(SYS_setsockopt, fd, level, name, value, len));
}

TCS_EXPORT int getsockopt(int fd, int level, int name, void *value, socklen_t *len)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->getsockopt)
		return tcs_errno_result(e.ops->getsockopt(fd, &e, level, name, value, len));
	return tcs_errno_result(tcs_sys5(SYS_getsockopt, fd, level, name, value, len));
}

/* ---- frames ----------------------------------------------------------------- */

TCS_EXPORT ssize_t recvmsg(int fd, struct msghdr *msg, int flags)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->recvmsg && tcs_active())
		return tcs_errno_result(e.ops->recvmsg(fd, &e, msg, flags));
	return tcs_errno_result(tcs_sys3(SYS_recvmsg, fd, msg, flags));
}

TCS_EXPORT ssize_t recvfrom(int fd, void *buf, size_t n, int flags, struct sockaddr *from, socklen_t *fromlen)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->recvmsg && tcs_active()) {
		struct iovec iov = { buf, n };
		struct msghdr mh = { .msg_name = from, .msg_namelen = from && fromlen ? *fromlen : 0, .msg_iov = &iov, .msg_iovlen = 1 };
		long r = e.ops->recvmsg(fd, &e, &mh, flags);
		if (r >= 0 && from && fromlen)
			*fromlen = mh.msg_namelen;
		return tcs_errno_result(r);
	}
	return tcs_errno_result(tcs_sys6(SYS_recvfrom, fd, buf, n, flags, from, fromlen));
}

TCS_EXPORT ssize_t recv(int fd, void *buf, size_t n, int flags)
{
	return recvfrom(fd, buf, n, flags, NULL, NULL);
}

/* The _FORTIFY_SOURCE variants (declared by no public header). */
TCS_EXPORT ssize_t __recv_chk(int fd, void *buf, size_t n, size_t buflen, int flags);
TCS_EXPORT ssize_t __recv_chk(int fd, void *buf, size_t n, size_t buflen, int flags)
{
	(void)buflen;
	return recvfrom(fd, buf, n, flags, NULL, NULL);
}

TCS_EXPORT ssize_t __recvfrom_chk(int fd, void *buf, size_t n, size_t buflen, int flags, struct sockaddr *from,
				  socklen_t *fromlen);
TCS_EXPORT ssize_t __recvfrom_chk(int fd, void *buf, size_t n, size_t buflen, int flags, struct sockaddr *from,
				  socklen_t *fromlen)
{
	(void)buflen;
	return recvfrom(fd, buf, n, flags, from, fromlen);
}

TCS_EXPORT ssize_t sendmsg(int fd, const struct msghdr *msg, int flags)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->sendmsg && tcs_active())
		return tcs_errno_result(e.ops->sendmsg(fd, &e, msg, flags));
	return tcs_errno_result(tcs_sys3(SYS_sendmsg, fd, msg, flags));
}

TCS_EXPORT ssize_t sendto(int fd, const void *buf, size_t n, int flags, const struct sockaddr *to, socklen_t tolen)
{
	struct tcs_fd e;
	if (tcs_fd_of(fd, &e) && e.ops->sendmsg && tcs_active()) {
		struct iovec iov = { (void *)buf, n };
		struct msghdr mh = { .msg_name = (void *)to, .msg_namelen = to ? tolen : 0, .msg_iov = &iov, .msg_iovlen = 1 };
		return tcs_errno_result(e.ops->sendmsg(fd, &e, &mh, flags));
	}
	return tcs_errno_result(tcs_sys6(SYS_sendto, fd, buf, n, flags, to, tolen));
}

TCS_EXPORT ssize_t send(int fd, const void *buf, size_t n, int flags)
{
	return sendto(fd, buf, n, flags, NULL, 0);
}

/* ---- interfaces ---------------------------------------------------------------- */

TCS_EXPORT unsigned int if_nametoindex(const char *name)
{
	int32_t ifindex = tcs_can_ifindex(name);
	if (ifindex > 0)
		return (unsigned int)ifindex;
	return tcs_real()->if_nametoindex(name);
}

TCS_EXPORT char *if_indextoname(unsigned int ifindex, char name[IF_NAMESIZE])
{
	const char *ours = ifindex <= 0x7fffffffu ? tcs_can_ifname((int32_t)ifindex) : NULL;
	if (!ours)
		return tcs_real()->if_indextoname(ifindex, name);
	size_t len = strnlen(ours, IF_NAMESIZE - 1);
	memcpy(name, ours, len);
	name[len] = 0;
	return name;
}
