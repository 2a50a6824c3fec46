/* This process as a descendant of a controller. A new child (forked, or
 * started by vfork or posix_spawn) registers with the coordinator and
 * becomes a controller of its own, with its own virtual CPU, starting at
 * its parent's virtual time; what it inherited of its parent's runtime is
 * put right. One the coordinator does not take on runs detached, in real
 * time, and says so once. The hooks that start children and wait for
 * them are hooks_process.c. */
#include <pthread.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <unistd.h>

#include "child.h"
#include "fd_table.h"
#include "journal_write.h"
#include "raw_syscall.h"
#include "report.h"
#include "roundtrip.h"
#include "signal_timers.h"
#include "spin_lock.h"
#include "tcs/msg_io.h"
#include "thread_channels.h"
#include "vclock.h"
#include "wait.h"

static int64_t tcs_fork_v; /* the parent's virtual time at the fork */

/* Sends CHILD on parent_channel and waits for the answer; on success the
 * new channel and clock page are at fds channel_no and page_no. 0 or -1. */
static int tcs_register_child(int parent_channel, int channel_no, int page_no, int64_t fork_v, int v_known)
{
	int sv[2];
	if (tcs_sys4(SYS_socketpair, AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, sv) < 0)
		return -1;
	struct tcs_msg m = tcs_msg_make(TCS_MSG_CHILD, 1);
	m.arg = tcs_sys0(SYS_getpid);
	m.v = v_known ? fork_v : 0;
	m.flags = v_known ? TCS_CHILD_V_KNOWN : 0;
	struct tcs_msg_io io;
	tcs_msg_io_send(&io, &m, sizeof m, sv[1]);
	long r;
	do
		r = tcs_sys3(SYS_sendmsg, parent_channel, &io.mh, MSG_NOSIGNAL);
	while (r == -EINTR);
	tcs_sys1(SYS_close, sv[1]);
	if (r != (long)sizeof m) {
		tcs_sys1(SYS_close, sv[0]);
		return -1;
	}
	struct tcs_msg w;
	tcs_msg_io_recv(&io, &w, sizeof w);
	do
		r = tcs_sys3(SYS_recvmsg, sv[0], &io.mh, MSG_CMSG_CLOEXEC);
	while (r == -EINTR);
	int page = r > 0 ? tcs_msg_io_fd(&io) : -1;
	if (r != (long)sizeof w || w.magic != TCS_PROTO_MAGIC || w.type != TCS_MSG_WAKE || w.arg != 0 || page < 0) {
		if (page >= 0)
			tcs_sys1(SYS_close, page);
		tcs_sys1(SYS_close, sv[0]);
		return -1;
	}
	/* Over the parent's channel and page in this process (not in the parent). */
	tcs_sys3(SYS_dup3, sv[0], channel_no, 0);
	tcs_sys1(SYS_close, sv[0]);
	tcs_sys3(SYS_dup3, page, page_no, 0);
	tcs_sys1(SYS_close, page);
	return 0;
}

int tcs_become_child(int parent_channel, int64_t fork_v, int v_known)
{
	struct tcs_clock_page *old = tcs_rt.page;
	/* What its parent's clocks had read by the fork, its clocks do not go
	 * back from: fork_v (a clock read), or, for a child of vfork or
	 * posix_spawn (no time known), the page's as it starts. Not the page's
	 * after registering: the parent's other threads read on meanwhile
	 * (in lockstep each read a spin's cost), and the child's clocks began
	 * that much past its fork (a sleep of a child of a threaded program
	 * measured 300 us long, under load 1 run in 15). */
	int64_t seen = v_known ? fork_v : old ? __atomic_load_n(&old->v_seen, __ATOMIC_RELAXED) : 0;
	if (tcs_register_child(parent_channel, tcs_rt.channel_fd, tcs_rt.page_fd, fork_v, v_known) < 0)
		return -1;
	if (old)
		tcs_sys2(SYS_munmap, old, TCS_SHARED_SIZE);
	tcs_rt.page = NULL;
	long m = tcs_sys6(SYS_mmap, NULL, TCS_SHARED_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, tcs_rt.page_fd, 0);
	if (m < 0 && m > -4096)
		return -1;
	tcs_rt.page = (struct tcs_clock_page *)m;
	tcs_rt.devices = tcs_device_table_of(tcs_rt.page);
	(void)tcs_v_not_before(seen);
	tcs_rt.pid = tcs_sys0(SYS_getpid);
	tcs_thread_channels_after_fork();
	tcs_cpu_forget(); /* a CPU clock of its own now, from 0 */
	tcs_timers_forget_all(); /* POSIX: timers are not inherited */
	tcs_fds_after_fork(); /* (its devices opened again as its own) */
	return 0;
}

/* The forking thread's signal mask before its tcs_locks_hold_all. */
static __thread uint64_t tcs_fork_mask;

static void tcs_atfork_prepare(void)
{
	if (tcs_active())
		tcs_fork_v = tcs_vnow();
	tcs_fork_mask = tcs_locks_hold_all();
}

static void tcs_atfork_parent(void)
{
	tcs_locks_release_all(tcs_fork_mask);
}

static void tcs_atfork_child(void)
{
	tcs_locks_release_all(tcs_fork_mask);
	if (tcs_rt.state != TCS_ON)
		return;
	/* The journal is its parent's: not a word of it is this process's. */
	tcs_journal_forget();
	tcs_calls_after_fork(tcs_fork_v);
	if (tcs_become_child(tcs_rt.channel_fd, tcs_fork_v, 1) == 0)
		return;
	tcs_rt.state = TCS_DETACHED;
	tcs_tell_detached(tcs_rt.page);
	tcs_sys1(SYS_close, tcs_rt.channel_fd);
	tcs_rt.channel_fd = -1;
}

void tcs_child_init(void)
{
	pthread_atfork(tcs_atfork_prepare, tcs_atfork_parent, tcs_atfork_child);
}

/* ---- running detached ---------------------------------------------------- */

/* A descendant of the controller is not what the coordinator schedules: it
 * runs in real time and says so once, with its pid. A fork followed by an
 * exec is one process, so the clock page remembers who has been told: the
 * forked child keeps the page fd open through exec for that, and nothing
 * else of the runtime. */
void tcs_tell_detached(struct tcs_clock_page *page)
{
	char pid[24], *p = pid + sizeof pid;
	long n = tcs_sys0(SYS_getpid), self = n;
	*--p = '\0';
	do
		*--p = (char)('0' + n % 10);
	while ((n /= 10) > 0);
	if (!page || __atomic_exchange_n(&page->detached_pid, self, __ATOMIC_RELAXED) != self)
		tcs_say("process ", p, ", started by the controller, runs in real time (the coordinator could not take it on)");
}

/* After exec in a descendant: the page fd, if it is still ours, tells
 * whether this process was already told (as a forked child). At start-up
 * only (the constructor may use libc). */
void tcs_detach_descendant(int page_fd)
{
	char link[64] = { 0 };
	char path[40] = "/proc/self/fd/";
	struct tcs_clock_page *page = NULL;
	char *d = path + 14, digits[12], *q = digits + sizeof digits;
	int fd = page_fd;
	*--q = '\0';
	do
		*--q = (char)('0' + fd % 10);
	while ((fd /= 10) > 0);
	while (*q)
		*d++ = *q++;
	*d = '\0';
	if (page_fd >= 0 && readlink(path, link, sizeof link - 1) > 0 &&
	    strncmp(link, "/memfd:tcs-clock-page", 21) == 0) {
		void *m = mmap(NULL, TCS_PAGE_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, page_fd, 0);
		if (m != MAP_FAILED)
			page = (struct tcs_clock_page *)m;
		tcs_sys1(SYS_close, page_fd); /* (not close(): that is the hook's) */
	}
	tcs_rt.state = TCS_DETACHED;
	tcs_tell_detached(page);
	if (page)
		munmap(page, TCS_PAGE_SIZE);
}
