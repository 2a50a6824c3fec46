/* Multiplexer hooks: select, pselect, poll, ppoll, epoll_wait, epoll_pwait,
 * epoll_pwait2 (and the fortified poll variants). The timeout is virtual;
 * the real fds are real. Each call first checks the fds without blocking;
 * if nothing is ready it waits for the virtual deadline while the kernel
 * watches the fds beside the channel, so a real fd that becomes ready ends
 * the wait at once (at the controller's current virtual time). Sets too big
 * to mirror on the stack are re-checked at every simulation step instead. */
#include <string.h>
#include <sys/epoll.h>
#include <sys/select.h>

#include "device_requests.h"
#include "fd_table.h"
#include "raw_syscall.h"
#include "spin.h"
#include "timer_slack.h"
#include "timerfds.h"
#include "vclock.h"
#include "wait.h"

/* Real fds mirrored on the stack while waiting (slot 0 is the channel). */
#define TCS_MIRROR_MAX 256

static const struct timespec tcs_zero_ts = { 0, 0 };

/* Non-blocking re-check of the real fds: >0 ready (results stored where the
 * program expects them), 0 nothing yet, <0 -errno. */
typedef long (*tcs_check_fn)(void *ctx);

/* The shared body of every multiplexer: check, then wait in virtual time
 * until something is ready or timeout_ns (< 0: forever) has passed. With
 * mirror == NULL the fds are re-checked at every step instead. *v_left
 * (may be NULL) receives the virtual time left of the timeout. */
static long tcs_multiplex(int64_t timeout_ns, tcs_check_fn check, void *ctx, struct pollfd *mirror,
			  unsigned nmirror, const sigset_t *mask, int64_t *v_left)
{
	/* With devices open, what is due on them must be in their fds before
	 * the kernel is asked what is ready, and the wait must end when the
	 * next record is due. */
	int devices = tcs_fds_served() > 0;
	if (devices) {
		long s = tcs_device_sync_held(0, -1, TCS_SYNC_POLL);
		if (s < 0)
			return s;
	}
	/* Virtual timerfds due by now are readable before the fds are checked;
	 * with any armed, the deadline is absolute, for waits end at expiries. */
	int timers = tcs_vtimers_armed();
	int64_t until = timeout_ns < 0 ? TCS_NEVER : timeout_ns, next_timer = TCS_NEVER;
	if (timers) {
		int64_t now = tcs_v_not_before(tcs_vnow());
		next_timer = tcs_vtimers_fire(now);
		if (timeout_ns >= 0)
			until = tcs_ns_add(now, timeout_ns);
	}
	long r = check(ctx);
	if (r == 0 && timeout_ns == 0)
		tcs_spin_empty_read(1); /* polled, nothing ready: a spin's, in lockstep */
	if (r != 0 || timeout_ns == 0)
		return r;
	/* Relative on the first wait; absolute (the same deadline) on any
	 * that follow a wake-up with nothing ready after all. */
	struct tcs_wait_time t = { until, timeout_ns >= 0 && !timers, 0, 0, 0, 0 };
	unsigned flags = (mirror ? 0 : TCS_BLOCK_RECHECK) | (devices ? TCS_BLOCK_DEVICES : 0);
	/* The timeout ends late by the slack its length gives it; a timer's
	 * expiry, exactly (timerfds have none, natively). */
	const int64_t slack = timeout_ns > 0 ? tcs_poll_slack(timeout_ns) : 0;
	t.slack = slack;
	for (;;) {
		/* Wake at the next timer expiry if it comes first. */
		if (timers) {
			t.deadline = next_timer < until ? next_timer : until;
			t.slack = next_timer <= until ? 0 : next_timer - until < slack ? next_timer - until : slack;
		}
		long w = tcs_wait(&t, TCS_BLOCK_POLL, flags, mirror, nmirror, mask);
		if (timers) {
			next_timer = tcs_vtimers_fire(t.end);
			t.deadline = until;
		}
		if (v_left)
			*v_left = t.deadline == TCS_NEVER ? TCS_NEVER : t.deadline > t.end ? t.deadline - t.end : 0;
		if (w == -EINTR)
			return -EINTR;
		r = check(ctx);
		if (r != 0 || (w == TCS_WAIT_DEADLINE && t.end >= t.deadline))
			return r;
	}
}

/* ---- poll / ppoll ---------------------------------------------------------- */

struct tcs_poll_ctx {
	struct pollfd *fds;
	nfds_t n;
	const sigset_t *mask;
};

static long tcs_poll_check(void *c)
{
	struct tcs_poll_ctx *x = (struct tcs_poll_ctx *)c;
	return tcs_sys5(SYS_ppoll, x->fds, x->n, &tcs_zero_ts, x->mask, TCS_KERNEL_SIGSET_SIZE);
}

/* timeout_ns < 0: forever. Returns the poll result or -errno. */
static long tcs_poll(struct pollfd *fds, nfds_t n, int64_t timeout_ns, const struct timespec *real_ts,
		     const sigset_t *mask)
{
	if (!tcs_wait_enter())
		return tcs_sys5(SYS_ppoll, fds, n, real_ts, mask, TCS_KERNEL_SIGSET_SIZE);
	struct tcs_poll_ctx ctx = { fds, n, mask };
	struct pollfd mirror[TCS_MIRROR_MAX];
	long r;
	if (n < TCS_MIRROR_MAX) {
		memcpy(mirror + 1, fds, n * sizeof *fds);
		r = tcs_multiplex(timeout_ns, tcs_poll_check, &ctx, mirror, (unsigned)n + 1, mask, NULL);
	} else {
		r = tcs_multiplex(timeout_ns, tcs_poll_check, &ctx, NULL, 0, mask, NULL);
	}
	tcs_wait_leave();
	return r;
}

static int64_t tcs_ms_to_ns(int ms)
{
	return ms < 0 ? -1 : (int64_t)ms * TCS_NS_PER_MS;
}

TCS_EXPORT int poll(struct pollfd *fds, nfds_t n, int timeout_ms)
{
	struct timespec ts = tcs_ns_to_ts(tcs_ms_to_ns(timeout_ms));
	return tcs_errno_result(tcs_poll(fds, n, tcs_ms_to_ns(timeout_ms), timeout_ms < 0 ? NULL : &ts, NULL));
}

/* _FORTIFY_SOURCE variants (declared by no public header). */
TCS_EXPORT int __poll_chk(struct pollfd *fds, nfds_t n, int timeout_ms, size_t fdslen);
TCS_EXPORT int __poll_chk(struct pollfd *fds, nfds_t n, int timeout_ms, size_t fdslen)
{
	(void)fdslen;
	return poll(fds, n, timeout_ms);
}

TCS_EXPORT int ppoll(struct pollfd *fds, nfds_t n, const struct timespec *ts, const sigset_t *mask)
{
	if (ts && !tcs_ts_valid(ts))
		return tcs_errno_result(-EINVAL);
	return tcs_errno_result(tcs_poll(fds, n, ts ? tcs_ts_to_ns(ts) : -1, ts, mask));
}

TCS_EXPORT int __ppoll_chk(struct pollfd *fds, nfds_t n, const struct timespec *ts, const sigset_t *mask,
			   size_t fdslen);
TCS_EXPORT int __ppoll_chk(struct pollfd *fds, nfds_t n, const struct timespec *ts, const sigset_t *mask,
			   size_t fdslen)
{
	(void)fdslen;
	return ppoll(fds, n, ts, mask);
}

/* ---- select / pselect ------------------------------------------------------ */

struct tcs_select_ctx {
	int nfds;
	fd_set *sets[3]; /* read, write, except; may be NULL */
	const sigset_t *mask;
	size_t bytes; /* of each set that nfds covers */
};

static long tcs_select_check(void *c)
{
	struct tcs_select_ctx *x = (struct tcs_select_ctx *)c;
	fd_set copy[3];
	fd_set *arg[3];
	for (int i = 0; i < 3; i++) {
		arg[i] = x->sets[i] ? &copy[i] : NULL;
		if (arg[i])
			memcpy(arg[i], x->sets[i], x->bytes);
	}
	struct {
		const sigset_t *ss;
		size_t len;
	} sig = { x->mask, TCS_KERNEL_SIGSET_SIZE };
	struct timespec zero = tcs_zero_ts;
	long r = tcs_sys6(SYS_pselect6, x->nfds, arg[0], arg[1], arg[2], &zero, x->mask ? (long)&sig : 0);
	if (r > 0)
		for (int i = 0; i < 3; i++)
			if (arg[i])
				memcpy(x->sets[i], arg[i], x->bytes);
	return r;
}

/* Mirrors the fds of the sets into pollfds after slot 0; 0 if too many. */
static unsigned tcs_select_mirror(const struct tcs_select_ctx *x, struct pollfd *mirror)
{
	static const short events[3] = { POLLIN, POLLOUT, POLLPRI };
	unsigned n = 1;
	for (int fd = 0; fd < x->nfds; fd++) {
		short ev = 0;
		for (int i = 0; i < 3; i++)
			if (x->sets[i] && FD_ISSET(fd, x->sets[i]))
				ev |= events[i];
		if (!ev)
			continue;
		if (n == TCS_MIRROR_MAX)
			return 0;
		mirror[n].fd = fd;
		mirror[n].events = ev;
		n++;
	}
	return n;
}

static long tcs_select(int nfds, fd_set *r, fd_set *w, fd_set *e, int64_t timeout_ns, const sigset_t *mask,
		       int64_t *v_left)
{
	struct tcs_select_ctx ctx = { nfds, { r, w, e }, mask, ((size_t)nfds + 63) / 64 * 8 };
	struct pollfd mirror[TCS_MIRROR_MAX];
	unsigned n = tcs_select_mirror(&ctx, mirror);
	long res = tcs_multiplex(timeout_ns, tcs_select_check, &ctx, n ? mirror : NULL, n, mask, v_left);
	if (res == 0)
		for (int i = 0; i < 3; i++)
			if (ctx.sets[i])
				memset(ctx.sets[i], 0, ctx.bytes);
	return res;
}

TCS_EXPORT int select(int nfds, fd_set *r, fd_set *w, fd_set *e, struct timeval *tv)
{
	if (nfds < 0 || (tv && (tv->tv_sec < 0 || tv->tv_usec < 0 || tv->tv_usec >= 1000000)))
		return tcs_errno_result(-EINVAL);
	int64_t timeout = tv ? (int64_t)tv->tv_sec * TCS_NS_PER_S + tv->tv_usec * TCS_NS_PER_US : -1;
	if (nfds > FD_SETSIZE || !tcs_wait_enter()) {
		struct timespec ts = tcs_ns_to_ts(timeout), *tsp = tv ? &ts : NULL;
		long res = tcs_sys6(SYS_pselect6, nfds, r, w, e, tsp, 0);
		if (tv)
			*tv = tcs_ns_to_tv(tcs_ts_to_ns(&ts));
		return tcs_errno_result(res);
	}
	int64_t left = timeout;
	long res = tcs_select(nfds, r, w, e, timeout, NULL, &left);
	tcs_wait_leave();
	if (tv) /* Linux reports the time not slept. */
		*tv = tcs_ns_to_tv(left < 0 ? 0 : left);
	return tcs_errno_result(res);
}

TCS_EXPORT int pselect(int nfds, fd_set *r, fd_set *w, fd_set *e, const struct timespec *ts, const sigset_t *mask)
{
	if (nfds < 0 || (ts && !tcs_ts_valid(ts)))
		return tcs_errno_result(-EINVAL);
	if (nfds > FD_SETSIZE || !tcs_wait_enter()) {
		struct timespec copy = ts ? *ts : tcs_zero_ts;
		struct {
			const sigset_t *ss;
			size_t len;
		} sig = { mask, TCS_KERNEL_SIGSET_SIZE };
		return tcs_errno_result(tcs_sys6(SYS_pselect6, nfds, r, w, e, ts ? &copy : NULL, mask ? (long)&sig : 0));
	}
	long res = tcs_select(nfds, r, w, e, ts ? tcs_ts_to_ns(ts) : -1, mask, NULL);
	tcs_wait_leave();
	return tcs_errno_result(res);
}

/* ---- epoll ------------------------------------------------------------------ */

struct tcs_epoll_ctx {
	int epfd;
	struct epoll_event *events;
	int max;
	const sigset_t *mask;
};

static long tcs_epoll_check(void *c)
{
	struct tcs_epoll_ctx *x = (struct tcs_epoll_ctx *)c;
	return tcs_sys6(SYS_epoll_pwait, x->epfd, x->events, x->max, 0, x->mask, TCS_KERNEL_SIGSET_SIZE);
}

static long tcs_epoll(int epfd, struct epoll_event *events, int max, int64_t timeout_ns, const sigset_t *mask)
{
	if (!tcs_wait_enter()) {
		int ms = timeout_ns < 0 ? -1 : (int)((timeout_ns + TCS_NS_PER_MS - 1) / TCS_NS_PER_MS);
		return tcs_sys6(SYS_epoll_pwait, epfd, events, max, ms, mask, TCS_KERNEL_SIGSET_SIZE);
	}
	struct tcs_epoll_ctx ctx = { epfd, events, max, mask };
	/* An epoll fd is itself readable while it has events to report. */
	struct pollfd mirror[2] = { { -1, 0, 0 }, { epfd, POLLIN, 0 } };
	long r = tcs_multiplex(timeout_ns, tcs_epoll_check, &ctx, mirror, 2, mask, NULL);
	tcs_wait_leave();
	return r;
}

TCS_EXPORT int epoll_wait(int epfd, struct epoll_event *events, int max, int timeout_ms)
{
	return tcs_errno_result(tcs_epoll(epfd, events, max, tcs_ms_to_ns(timeout_ms), NULL));
}

TCS_EXPORT int epoll_pwait(int epfd, struct epoll_event *events, int max, int timeout_ms, const sigset_t *mask)
{
	return tcs_errno_result(tcs_epoll(epfd, events, max, tcs_ms_to_ns(timeout_ms), mask));
}

TCS_EXPORT int epoll_pwait2(int epfd, struct epoll_event *events, int max, const struct timespec *ts,
			    const sigset_t *mask)
{
	if (ts && !tcs_ts_valid(ts))
		return tcs_errno_result(-EINVAL);
	return tcs_errno_result(tcs_epoll(epfd, events, max, ts ? tcs_ts_to_ns(ts) : -1, mask));
}
