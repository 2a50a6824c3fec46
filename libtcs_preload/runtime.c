/* The preload's runtime: attaching to the coordinator when the library is
 * loaded, reading virtual time from the clock page, and waiting in virtual
 * time over the channel. Hooks (hooks_*.c) are thin wrappers around this.
 *
 * tcs_init() runs as a constructor, single-threaded, before main(); it may
 * use libc freely. Everything else here runs inside hooks and follows the
 * rules in preload.h. */
#include <fcntl.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/socket.h>

#include "devices.h"
#include "preload.h"
#include "mailbox.h"
#include "raw_syscall.h"

struct tcs_runtime tcs_rt = { .state = TCS_OFF, .channel_fd = -1, .page_fd = -1 };
__thread int tcs_in_wait;

/* Writes "tcs: " a b c "\n" to stderr in one write (any part may be NULL). */
static void tcs_write_stderr(const char *a, const char *b, const char *c)
{
	char buf[256];
	size_t n = 0;
	for (const char *parts[] = { "tcs: ", a, b, c, "\n" }, **q = parts; q < parts + 5; q++)
		for (const char *ch = *q; ch && *ch && n < sizeof buf; ch++)
			buf[n++] = *ch;
	tcs_sys3(SYS_write, 2, buf, n);
}

void tcs_report_once(int *once, const char *msg)
{
	if (__atomic_exchange_n(once, 1, __ATOMIC_RELAXED) == 0)
		tcs_write_stderr(msg, NULL, NULL);
}

/* The coordinator is gone or spoke nonsense: there is no virtual time left
 * to give this program, and running on in real time would be a silent lie. */
static __attribute__((noreturn)) void tcs_lost(const char *why)
{
	tcs_write_stderr("lost the coordinator: ", why, NULL);
	tcs_sys2(SYS_kill, tcs_sys0(SYS_getpid), SIGKILL);
	for (;;)
		tcs_sys1(SYS_exit_group, 2);
}

int64_t tcs_kernel_clock(clockid_t id)
{
	struct timespec ts;
	long r = tcs_sys2(SYS_clock_gettime, id, &ts);
	return r < 0 ? r : tcs_ts_to_ns(&ts);
}

/* A machine whose CPU-clock system call is slow, imitated for the test
 * suite's slow-clock setup (TCS_CPU_CLOCK_DELAY_NS, read at load): each
 * reading computes that much longer, half before the kernel reads the clock
 * and half after, as the system call's own entry and exit would. */
static int64_t tcs_cpu_clock_delay;

static void tcs_compute_for(int64_t ns)
{
	int64_t until = tcs_kernel_clock(CLOCK_MONOTONIC) + ns;
	while (tcs_kernel_clock(CLOCK_MONOTONIC) < until)
		tcs_cpu_relax();
}

int64_t tcs_process_cpu(void)
{
	if (__builtin_expect(tcs_cpu_clock_delay == 0, 1))
		return tcs_kernel_clock(CLOCK_PROCESS_CPUTIME_ID);
	tcs_compute_for(tcs_cpu_clock_delay / 2);
	int64_t cpu = tcs_kernel_clock(CLOCK_PROCESS_CPUTIME_ID);
	tcs_compute_for(tcs_cpu_clock_delay - tcs_cpu_clock_delay / 2);
	return cpu;
}

/* Estimates of CPU time (cpu_estimate.c) may run ahead of a later exact
 * reading, and the clock must not go back: tcs_v_not_before(). */
int64_t tcs_v_seen;

/* The latest exact CPU reading behind a CPU-time clock the program read:
 * what a wait charges is never less (see tcs_wait). */
static int64_t tcs_cpu_seen;

/* The latest CPU time the program was told: the credit for the runtime's
 * own reads is at most what a reading costs (cpu_estimate.c), but a reading
 * may still have cost less CPU than that by a few nanoseconds, and the
 * program's CPU-time clock must not go back for that. */
static int64_t tcs_charged_seen;

void tcs_cpu_forget(void)
{
	__atomic_store_n(&tcs_cpu_seen, 0, __ATOMIC_RELAXED);
	__atomic_store_n(&tcs_charged_seen, 0, __ATOMIC_RELAXED);
#if defined(__x86_64__)
	tcs_anchor.valid = 0;
	tcs_anchor.v_valid = 0;
#endif
}

int64_t tcs_charge_point(void)
{
	/* Estimated (the coordinator bounds it by its own reading), but never
	 * below a CPU time the program has already read: an estimate can fall
	 * short by an interrupt charged to the process, and its CPU-time clock
	 * would go back. */
	int64_t cpu = tcs_process_cpu_estimate();
	int64_t seen = __atomic_load_n(&tcs_cpu_seen, __ATOMIC_RELAXED);
	return cpu < seen ? seen : cpu;
}

int64_t tcs_charged_now(void)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	int64_t cpu = tcs_process_cpu();
	if (cpu > __atomic_load_n(&tcs_cpu_seen, __ATOMIC_RELAXED))
		__atomic_store_n(&tcs_cpu_seen, cpu, __ATOMIC_RELAXED);
	int64_t charged = tcs_page_charged(p, tcs_page_read_slice(p), cpu);
	int64_t seen = __atomic_load_n(&tcs_charged_seen, __ATOMIC_RELAXED);
	if (charged < seen)
		return seen;
	__atomic_store_n(&tcs_charged_seen, charged, __ATOMIC_RELAXED);
	return charged;
}

int64_t tcs_sleep_clock_origin(clockid_t id)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	switch (id) {
	case CLOCK_REALTIME:
	case CLOCK_REALTIME_ALARM:
		return p->real_origin_ns;
	case CLOCK_MONOTONIC:
	case CLOCK_BOOTTIME:
	case CLOCK_BOOTTIME_ALARM:
		return p->mono_origin_ns;
	case CLOCK_TAI:
		return p->tai_origin_ns;
	default:
		return -EINVAL;
	}
}

int tcs_wait_enter(void)
{
	if (!tcs_active() || tcs_in_wait)
		return 0;
	if (tcs_my_channel() < 0) {
		static int once;
		tcs_report_once(&once, "a thread could not get a channel to the coordinator (out of file descriptors?); "
				       "its waits run in real time");
		return 0;
	}
	tcs_in_wait = 1;
	return 1;
}

void tcs_wait_leave(void)
{
	/* Signals a handler sent from inside this wait, told now. */
	if (__builtin_expect(tcs_npending_kills != 0, 0))
		tcs_flush_kills();
	tcs_in_wait = 0;
}

static void tcs_send(int fd, const struct tcs_msg *m)
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

/* Timer signals due during a wait: raised here, inside the wait, so that
 * they meet the wait's signal mask; then the kernel says whether a handler
 * ran (EINTR) or not (ignored, or blocked: wait on). */
static int tcs_raise_timer_signals(uint64_t bits, const sigset_t *mask)
{
	/* Blocked while raised (a signal sent to oneself is delivered on the
	 * way out of kill), then let in by the wait's mask in a ppoll that
	 * does not wait. */
	uint64_t old;
	tcs_sys4(SYS_rt_sigprocmask, SIG_BLOCK, &bits, &old, TCS_KERNEL_SIGSET_SIZE);
	long pid = tcs_sys0(SYS_getpid);
	for (int sig = 1; sig <= 64; sig++) {
		if (!(bits & (1ull << (sig - 1))))
			continue;
		int tid = tcs_timer_signal_target(sig);
		if (tid > 0)
			tcs_sys3(SYS_tgkill, pid, tid, sig);
		else
			tcs_sys2(SYS_kill, pid, sig);
	}
	struct timespec zero = { 0, 0 };
	long r = tcs_sys5(SYS_ppoll, NULL, 0, &zero, mask ? (const void *)mask : (const void *)&old,
			  TCS_KERNEL_SIGSET_SIZE);
	tcs_sys4(SYS_rt_sigprocmask, SIG_SETMASK, &old, NULL, TCS_KERNEL_SIGSET_SIZE);
	return r == -EINTR ? -EINTR : TCS_WAIT_RECHECK;
}

/* Awake after the coordinator stepped us aside (TCS_PAGE_ASLEEP): a wait
 * already due, which the coordinator answers at the world's time
 * (TCS_BLOCK_ASK). It was a wait of 1 ns: when the coordinator had seen us
 * wake just before (a new slice, the flag not yet cleared), it ended 1 ns
 * after the world's time, and a lockstep run was 1 ns long (1 in 40 runs
 * under load). */
static __thread int tcs_catching_up;

static void tcs_catch_up_in_wait(void)
{
	if (tcs_catching_up)
		return;
	tcs_catching_up = 1;
	struct tcs_wait_time t = { 0, 1, 0, 0, 0 };
	(void)tcs_wait(&t, TCS_BLOCK_SLEEP, TCS_BLOCK_ASK, NULL, 0, NULL);
	tcs_catching_up = 0;
}

void tcs_catch_up(void)
{
	if (!tcs_wait_enter())
		return; /* inside a hook (a signal handler's clock read): it asks itself */
	tcs_catch_up_in_wait();
	tcs_wait_leave();
}

int tcs_wait(struct tcs_wait_time *t, unsigned kind, unsigned flags, struct pollfd *fds, unsigned nfds,
	     const sigset_t *mask)
{
	struct tcs_clock_page *p = tcs_rt.page;
	if (__builtin_expect(__atomic_load_n(&p->flags, __ATOMIC_RELAXED) & TCS_PAGE_ASLEEP, 0))
		tcs_catch_up_in_wait();
	/* The charge up to here, and virtual time from it in cpu mode. */
	int64_t cpu = tcs_charge_point();
	int64_t v = tcs_page_vnow(p, tcs_page_read_slice(p), cpu);
	/* A relative wait counts from the latest time the program was told,
	 * so it never sees a sleep end before it should have. */
	int64_t deadline = t->relative ? tcs_ns_add(tcs_v_not_before(v), t->deadline) : t->deadline;
	t->deadline = deadline;
	t->relative = 0;
	t->start = v;
	int report = (flags & TCS_BLOCK_ABSOLUTE) && (p->flags & TCS_PAGE_REPORT_MISSES);
	if (deadline <= v && !report && !(flags & TCS_BLOCK_ASK)) {
		__atomic_add_fetch(&p->quick_returns, 1, __ATOMIC_RELAXED);
		if (flags & TCS_BLOCK_ABSOLUTE)
			__atomic_add_fetch(&p->past_deadlines, 1, __ATOMIC_RELAXED);
		t->end = v;
		return TCS_WAIT_DEADLINE;
	}

	/* A wait with its own signal mask (sigsuspend, ppoll, pselect,
	 * epoll_pwait) may let in a signal already pending: then it ends now,
	 * before the coordinator could decide anything else. */
	uint64_t raised = 0;
	if (mask) {
		/* What tcs had raised before the look (TCS_BLOCK_SIGMASK): one it
		 * raises after, stopping us between the look and the BLOCK, is
		 * pending unseen, and the coordinator has us look again. */
		raised = __atomic_load_n(&p->signals_raised, __ATOMIC_ACQUIRE);
		struct timespec zero = { 0, 0 };
		if (tcs_sys5(SYS_ppoll, NULL, 0, &zero, mask, TCS_KERNEL_SIGSET_SIZE) == -EINTR) {
			t->end = v;
			return -EINTR;
		}
		flags |= TCS_BLOCK_SIGMASK;
	}

	struct tcs_msg m = tcs_msg_make(TCS_MSG_BLOCK, t->seq);
	m.kind = (uint16_t)kind;
	m.flags = (uint16_t)flags;
	m.arg = (int64_t)raised;
	m.deadline = deadline;
	m.v = v;
	m.cpu = cpu;
	struct tcs_msg w;
	unsigned early = tcs_roundtrip(&m, fds, nfds, mask, &w, NULL);
	t->end = w.v;
	/* A handler ran (a timer's signal, say): the wait was interrupted,
	 * whatever the answer that crossed the EARLY says. */
	if (early == TCS_EARLY_SIGNAL)
		return -EINTR;
	if (w.kind == TCS_WAKE_SIGNAL)
		return tcs_raise_timer_signals((uint64_t)w.arg, mask);
	if (w.kind == TCS_WAKE_RECHECK)
		return TCS_WAIT_RECHECK;
	if (w.kind == TCS_WAKE_EARLY)
		return TCS_WAIT_FD;
	return TCS_WAIT_DEADLINE;
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

/* ---- attaching, in the order it happens ---------------------------------- */

static int tcs_env_int(const char *name, long *out)
{
	const char *s = getenv(name);
	char *end;
	if (!s || !*s)
		return -ENOENT;
	*out = strtol(s, &end, 10);
	return *end == '\0' ? 0 : -EINVAL;
}

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
		tcs_write_stderr("process ", p,
				 ", started by the controller, runs in real time (the coordinator could not take it on)");
}

/* After exec in a descendant: the page fd, if it is still ours, tells
 * whether this process was already told (as a forked child). */
static void tcs_detach_descendant(int page_fd)
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
		close(page_fd);
	}
	tcs_rt.state = TCS_DETACHED;
	tcs_tell_detached(page);
	if (page)
		munmap(page, TCS_PAGE_SIZE);
}

static int tcs_read_environment(long *channel, long *page, long *controller)
{
	if (tcs_env_int(TCS_ENV_CHANNEL_FD, channel) || tcs_env_int(TCS_ENV_PAGE_FD, page) ||
	    tcs_env_int(TCS_ENV_CONTROLLER_PID, controller))
		return -ENOENT;
	return 0;
}

static int tcs_map_page(void)
{
	void *m = mmap(NULL, TCS_SHARED_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, tcs_rt.page_fd, 0);
	if (m == MAP_FAILED)
		return -errno;
	tcs_rt.page = (struct tcs_clock_page *)m;
	tcs_rt.devices = tcs_device_table_of(m);
	if (tcs_rt.page->magic != TCS_PAGE_MAGIC || tcs_rt.page->version != TCS_PAGE_VERSION)
		return -EPROTO;
	return 0;
}

static void tcs_say_hello(void)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_HELLO, 0);
	m.arg = tcs_sys0(SYS_getpid);
	/* Tells this program image from the one before an exec: a HELLO with
	 * the same value again is a misbehaving program, not a new image. */
	m.v = tcs_kernel_clock(CLOCK_MONOTONIC);
	tcs_send(tcs_rt.channel_fd, &m);
}

__attribute__((constructor)) static void tcs_init(void)
{
	long channel, page, controller;
	int saved_errno = errno;

	tcs_real_resolve();
	tcs_threads_init();
	long delay;
	if (tcs_env_int("TCS_CPU_CLOCK_DELAY_NS", &delay) == 0 && delay > 0)
		tcs_cpu_clock_delay = delay;
	if (tcs_read_environment(&channel, &page, &controller) < 0) {
		tcs_write_stderr("libtcs_preload.so loaded outside tcs-run; this program runs in real time", NULL, NULL);
		goto out;
	}
	(void)controller; /* the page says whose it is */
	tcs_rt.pid = tcs_sys0(SYS_getpid);
	tcs_rt.channel_fd = (int)channel;
	tcs_rt.page_fd = (int)page;
	int r = tcs_map_page();
	if (r < 0 && r != -EPROTO) {
		/* No page of ours: a descendant that closed it, or a stray. */
		tcs_detach_descendant(-1);
		goto out;
	}
	if (r < 0) {
		tcs_write_stderr("libtcs_preload.so does not match the coordinator (mixed installations?)",
				 "; refusing to run in real time", NULL);
		tcs_sys1(SYS_exit_group, 2);
	}
	if (tcs_rt.page->owner_pid != tcs_rt.pid) {
		/* A child started by vfork or posix_spawn, its new program just
		 * loaded, the page its parent's: it registers now. */
		if (tcs_become_child((int)channel, 0, 0) < 0) {
			struct tcs_clock_page *parents = tcs_rt.page;
			tcs_rt.page = NULL;
			tcs_rt.state = TCS_DETACHED;
			tcs_tell_detached(parents);
			tcs_sys2(SYS_munmap, parents, TCS_SHARED_SIZE);
			goto out;
		}
	}
	tcs_children_init();
	tcs_say_hello();
	__atomic_store_n(&tcs_rt.state, TCS_ON, __ATOMIC_RELEASE);
out:
	errno = saved_errno;
}
