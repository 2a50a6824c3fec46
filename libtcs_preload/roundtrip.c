/* One request to the coordinator and its answer (roundtrip.h). Every
 * request of this library goes through tcs_roundtrip: a wait's BLOCK, a
 * device's sync, a timer, a child, a signal's news. Runs inside hooks,
 * signal handlers included. */
#include <sys/socket.h>

#include "cpu_estimate.h"
#include "journal.h"
#include "lazy_writes.h"
#include "mailbox.h"
#include "raw_syscall.h"
#include "report.h"
#include "roundtrip.h"
#include "tcs/msg_io.h"
#include "thread_channels.h"

/* The coordinator is gone or spoke nonsense: there is no virtual time left
 * to give this program, and running on in real time would be a silent lie. */
static __attribute__((noreturn)) void tcs_lost(const char *why)
{
	tcs_say("lost the coordinator: ", why, NULL);
	tcs_sys2(SYS_kill, tcs_sys0(SYS_getpid), SIGKILL);
	for (;;)
		tcs_sys1(SYS_exit_group, 2);
}

void tcs_send(int fd, const struct tcs_msg *m)
{
	long r;
	do
		r = tcs_sys6(SYS_sendto, fd, (long)m, sizeof *m, MSG_NOSIGNAL, 0, 0);
	while (r == -EINTR);
	if (r != (long)sizeof *m)
		tcs_lost("the channel is closed");
}

static void tcs_send_early(int fd, uint32_t seq, unsigned reason)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_EARLY, seq);
	m.kind = (uint16_t)reason;
	tcs_send(fd, &m);
}

unsigned tcs_roundtrip(struct tcs_msg *m, struct pollfd *fds, unsigned nfds, const sigset_t *mask,
		       struct tcs_msg *reply, int *fd_out)
{
	uint32_t seq = m->seq ? m->seq : __atomic_add_fetch(&tcs_rt.next_seq, 1, __ATOMIC_RELAXED);
	m->seq = seq;
	int channel = tcs_my_channel();
	if (channel < 0)
		tcs_lost("this thread has no channel");
	if (fd_out)
		*fd_out = -1;
	/* On a core of its own, beside the coordinator polling on its own: no
	 * system call at all, unless it must be rung or the answer is slow. */
	unsigned early = 0;
	const int mailbox = !fds && !mask && !fd_out && tcs_mailbox_fits(m, channel);
	if (mailbox) {
		if (tcs_mailbox_post(m)) {
			struct tcs_msg ring = tcs_msg_make(TCS_MSG_DOORBELL, seq);
			tcs_send(channel, &ring);
		}
		tcs_lazy_request_sent();
		if (tcs_mailbox_wait(reply)) {
			if (reply->seq != seq || reply->type != TCS_MSG_WAKE)
				tcs_lost("unexpected answer in the mailbox");
			goto answered;
		}
		/* Parked: the answer comes on the channel. */
	} else {
		tcs_send(channel, m);
		tcs_lazy_request_sent();
	}

	/* Wait in ppoll, never in a blocking recv: ppoll is the one wait the
	 * kernel never restarts after a signal handler, SA_RESTART or not (so a
	 * handler is noticed, as a real sleep would be), and always restarts
	 * transparently after the coordinator's SIGSTOP/SIGCONT. */
	struct pollfd own;
	if (!fds) {
		fds = &own;
		nfds = 1;
	}
	/* Under SCHED_FIFO on our core the coordinator ran as soon as we sent:
	 * a reply it could give at once is already there. */
	const uint32_t here = TCS_PAGE_FIFO | TCS_PAGE_SHARES_CORE;
	int look_first = !mailbox && (__atomic_load_n(&tcs_rt.page->flags, __ATOMIC_RELAXED) & here) == here;
	for (;;) {
		if (!early && !look_first) {
			fds[0].fd = channel;
			fds[0].events = POLLIN;
			fds[0].revents = 0;
			long r = tcs_sys5(SYS_ppoll, fds, nfds, NULL, mask, TCS_KERNEL_SIGSET_SIZE);
			if (r == -EINTR || (r >= 0 && fds[0].revents == 0)) {
				early = r == -EINTR ? TCS_EARLY_SIGNAL : TCS_EARLY_FD;
				tcs_send_early(channel, seq, early);
				continue;
			}
			if (r < 0)
				tcs_lost("ppoll on the channel failed");
		}
		/* recvmsg: a reply to DEV_OPEN carries the device's fd. */
		struct tcs_msg_io io;
		tcs_msg_io_recv(&io, reply, sizeof *reply);
		long r = tcs_sys3(SYS_recvmsg, channel, &io.mh, MSG_CMSG_CLOEXEC | (look_first ? MSG_DONTWAIT : 0));
		if (look_first) {
			look_first = 0;
			if (r == -EAGAIN)
				continue; /* not yet: wait for it in ppoll */
		}
		if (r == -EINTR) {
			if (!early) {
				early = TCS_EARLY_SIGNAL;
				tcs_send_early(channel, seq, early);
			}
			continue;
		}
		if (r != (long)sizeof *reply || reply->magic != TCS_PROTO_MAGIC || reply->type != TCS_MSG_WAKE)
			tcs_lost(r == 0 ? "the channel is closed" : "unexpected message");
		int fd = tcs_msg_io_fd(&io);
		if (reply->seq != seq) {
			if (fd >= 0)
				tcs_sys1(SYS_close, fd);
			continue;
		}
		if (fd_out)
			*fd_out = fd;
		else if (fd >= 0)
			tcs_sys1(SYS_close, fd);
		break;
	}
answered:
	if (mailbox)
		tcs_mailbox_done();
	if (__builtin_expect(tcs_journal_on(), 0))
		tcs_journal_answered(m->type, reply->deadline);
	/* From here on the hook's own cost is not charged to the program. The
	 * mark is the process's CPU, which only means this hook's cost while
	 * the process has one thread: with more, another may have computed
	 * between the coordinator's resume and this thread's turn, and that is
	 * theirs to be charged (as on_block charges a threaded BLOCK to the
	 * coordinator's reading, not the hook's entry). */
	if ((reply->flags & TCS_WAKE_STARTS_SLICE) &&
	    __atomic_load_n(&tcs_rt.page->threads_started, __ATOMIC_RELAXED) == 0) {
		__atomic_store_n(&tcs_rt.page->exit_cpu, tcs_exit_mark(m->cpu), __ATOMIC_RELAXED);
		tcs_anchor_forget_v(); /* a read in between saw the old mark */
	}
	return early;
}
