/* The channels of a controller's threads (thread_channels.h). Each thread
 * waits on a channel of its own (see protocol.h): the main thread on the
 * controller's, every other one on a channel it makes at its first wait
 * and that closes when it ends. The table of those fds lets the descriptor
 * hooks keep them out of a program's reach, and a forked child drop them
 * (it has one thread). */
#include <fcntl.h>
#include <pthread.h>
#include <sys/socket.h>

#include "raw_syscall.h"
#include "spin_lock.h"
#include "tcs/msg_io.h"
#include "thread_channels.h"

#define TCS_MAX_THREAD_CHANNELS 256

static __thread int tcs_channel = -1; /* this thread's channel; -1: none yet */
static int tcs_thread_fds[TCS_MAX_THREAD_CHANNELS];
static int tcs_thread_fd_count; /* slots in use, for the fast path */
static pthread_key_t tcs_thread_key;

static void tcs_thread_fd_remember(int fd, int add)
{
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_THREAD_FDS]);
	for (int i = 0; i < TCS_MAX_THREAD_CHANNELS; i++) {
		if (add ? tcs_thread_fds[i] == 0 : tcs_thread_fds[i] == fd + 1) {
			tcs_thread_fds[i] = add ? fd + 1 : 0;
			__atomic_add_fetch(&tcs_thread_fd_count, add ? 1 : -1, __ATOMIC_RELAXED);
			break;
		}
	}
	tcs_unlock(&tcs_locks[TCS_LOCK_THREAD_FDS], signals);
}

int tcs_is_thread_channel(int fd)
{
	if (__atomic_load_n(&tcs_thread_fd_count, __ATOMIC_RELAXED) == 0)
		return 0;
	for (int i = 0; i < TCS_MAX_THREAD_CHANNELS; i++)
		if (__atomic_load_n(&tcs_thread_fds[i], __ATOMIC_RELAXED) == fd + 1)
			return 1;
	return 0;
}

int tcs_thread_channels(int *out, int max)
{
	int n = 0;
	for (int i = 0; i < TCS_MAX_THREAD_CHANNELS && n < max; i++) {
		int v = __atomic_load_n(&tcs_thread_fds[i], __ATOMIC_RELAXED);
		if (v > 0)
			out[n++] = v - 1;
	}
	return n;
}

/* The thread ends: its channel closes, which tells the coordinator. */
static void tcs_thread_ended(void *value)
{
	int fd = (int)(long)value - 1;
	tcs_thread_fd_remember(fd, 0);
	tcs_sys1(SYS_close, fd);
	tcs_channel = -1;
}

/* A new channel for this thread, handed to the coordinator; -errno. */
static int tcs_thread_channel_make(void)
{
	int sv[2];
	long r = tcs_sys4(SYS_socketpair, AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, sv);
	if (r < 0)
		return (int)r;
	/* Out of the program's way, as the runtime's other fds. */
	long fd = tcs_sys3(SYS_fcntl, sv[0], F_DUPFD_CLOEXEC, TCS_RUNTIME_FD_FLOOR);
	tcs_sys1(SYS_close, sv[0]);
	if (fd < 0) {
		tcs_sys1(SYS_close, sv[1]);
		return (int)fd;
	}
	struct tcs_msg m = tcs_msg_make(TCS_MSG_THREAD, 0);
	m.arg = tcs_sys0(SYS_gettid);
	struct tcs_msg_io io;
	tcs_msg_io_send(&io, &m, sizeof m, sv[1]);
	do
		r = tcs_sys3(SYS_sendmsg, tcs_rt.channel_fd, &io.mh, MSG_NOSIGNAL);
	while (r == -EINTR);
	tcs_sys1(SYS_close, sv[1]);
	if (r != (long)sizeof m) {
		tcs_sys1(SYS_close, fd);
		return -EPIPE;
	}
	tcs_thread_fd_remember((int)fd, 1);
	pthread_setspecific(tcs_thread_key, (void *)(fd + 1));
	return (int)fd;
}

int tcs_my_channel(void)
{
	if (tcs_channel >= 0)
		return tcs_channel;
	if (tcs_sys0(SYS_gettid) == tcs_rt.pid)
		return tcs_channel = tcs_rt.channel_fd;
	int fd = tcs_thread_channel_make();
	if (fd >= 0)
		tcs_channel = fd;
	return fd;
}

void tcs_thread_channels_after_fork(void)
{
	int fds[TCS_MAX_THREAD_CHANNELS];
	int n = tcs_thread_channels(fds, TCS_MAX_THREAD_CHANNELS);
	for (int i = 0; i < n; i++)
		tcs_sys1(SYS_close, fds[i]);
	for (int i = 0; i < TCS_MAX_THREAD_CHANNELS; i++)
		tcs_thread_fds[i] = 0;
	tcs_thread_fd_count = 0;
	tcs_channel = -1;
	pthread_setspecific(tcs_thread_key, NULL);
}

void tcs_thread_channels_init(void)
{
	pthread_key_create(&tcs_thread_key, tcs_thread_ended);
}
