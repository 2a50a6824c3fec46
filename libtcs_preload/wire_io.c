/* Wire packets and waits (see wire_io.h). A packet goes whole: a stream
 * socket's send may take part of it when the fd is non-blocking and its
 * buffer full, so the rest follows once the coordinator has taken what is
 * there. A read that may not wait asks as non-blocking whatever the fd's
 * flags say. */
#include "wire_io.h"

#include <fcntl.h>
#include <sys/socket.h>

#include "device_requests.h"
#include "raw_syscall.h"
#include "report.h"
#include "spin.h"
#include "tcs/wire_protocol.h"
#include "wait.h"

static long tcs_wire_request(int fd, int h, unsigned kind, int wait, int64_t deadline)
{
	if (!tcs_wait_enter())
		return 0; /* (no channel for this thread: said once) */
	(void)fd;
	long r = tcs_device_sync_until(h, kind, !wait, deadline);
	if (r == -EAGAIN)
		tcs_spin_empty_read(1);
	tcs_wait_leave();
	return r;
}

long tcs_wire_send(int fd, int h, uint32_t type, const void *payload, size_t len)
{
	if (len > TCS_WIRE_PAYLOAD_MAX)
		return -EMSGSIZE;
	struct tcs_wire_head head = { type, (uint32_t)len };
	struct iovec iov[2] = { { &head, sizeof head }, { (void *)payload, len } };
	struct msghdr mh = { 0 };
	size_t left = sizeof head + len;
	while (left > 0) {
		mh.msg_iov = iov;
		mh.msg_iovlen = 2;
		long n = tcs_sys3(SYS_sendmsg, fd, &mh, MSG_NOSIGNAL | MSG_DONTWAIT);
		if (n == -EAGAIN) {
			long r = tcs_wire_request(fd, h, TCS_SYNC_WRITE, 1, -1);
			if (r < 0)
				return r;
			continue;
		}
		if (n < 0)
			return n;
		left -= (size_t)n;
		for (int i = 0; i < 2 && n > 0; i++) {
			size_t k = (size_t)n < iov[i].iov_len ? (size_t)n : iov[i].iov_len;
			iov[i].iov_base = (char *)iov[i].iov_base + k;
			iov[i].iov_len -= k;
			n -= (long)k;
		}
	}
	return tcs_wire_request(fd, h, TCS_SYNC_WRITE, 1, -1);
}

long tcs_wire_sync(int fd, int h, int wait, int64_t deadline)
{
	return tcs_wire_request(fd, h, TCS_SYNC_READ, wait, deadline);
}
