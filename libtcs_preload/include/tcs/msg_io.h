/* One protocol message with at most one file descriptor (SCM_RIGHTS) over
 * the SOCK_SEQPACKET channel, as both sides pass them: the preload (raw
 * system calls) and the coordinator (libc) each make the call, this header
 * fills in the message header and reads what came. A control buffer of one
 * fd means the kernel drops any further fds a hostile peer sends. */
#ifndef TCS_MSG_IO_H
#define TCS_MSG_IO_H

#include <stddef.h>
#include <sys/socket.h>
#include <sys/uio.h>

#ifdef __cplusplus
extern "C" {
#endif

struct tcs_msg_io {
	struct iovec iov;
	struct msghdr mh;
	union {
		struct cmsghdr align;
		char buf[CMSG_SPACE(sizeof(int))];
	} control;
};

/* For sendmsg(&io->mh): len bytes of msg, and fd with them if fd >= 0. */
static inline void tcs_msg_io_send(struct tcs_msg_io *io, const void *msg, size_t len, int fd)
{
	__builtin_memset(io, 0, sizeof *io);
	io->iov.iov_base = (void *)msg;
	io->iov.iov_len = len;
	io->mh.msg_iov = &io->iov;
	io->mh.msg_iovlen = 1;
	if (fd < 0)
		return;
	io->mh.msg_control = io->control.buf;
	io->mh.msg_controllen = sizeof io->control.buf;
	struct cmsghdr *c = CMSG_FIRSTHDR(&io->mh);
	c->cmsg_level = SOL_SOCKET;
	c->cmsg_type = SCM_RIGHTS;
	c->cmsg_len = CMSG_LEN(sizeof(int));
	__builtin_memcpy(CMSG_DATA(c), &fd, sizeof fd);
}

/* For recvmsg(&io->mh): up to len bytes into buf, and room for one fd. */
static inline void tcs_msg_io_recv(struct tcs_msg_io *io, void *buf, size_t len)
{
	__builtin_memset(io, 0, sizeof *io);
	io->iov.iov_base = buf;
	io->iov.iov_len = len;
	io->mh.msg_iov = &io->iov;
	io->mh.msg_iovlen = 1;
	io->mh.msg_control = io->control.buf;
	io->mh.msg_controllen = sizeof io->control.buf;
}

/* After a recvmsg: the fd that came with the message (now the caller's to
 * close), or -1. */
static inline int tcs_msg_io_fd(struct tcs_msg_io *io)
{
	struct cmsghdr *c = CMSG_FIRSTHDR(&io->mh);
	int fd = -1;
	if (c && c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_RIGHTS && c->cmsg_len >= CMSG_LEN(sizeof(int)))
		__builtin_memcpy(&fd, CMSG_DATA(c), sizeof fd);
	return fd;
}

#ifdef __cplusplus
}
#endif
#endif
