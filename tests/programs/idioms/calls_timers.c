/* The idioms program's calls on interval timers, POSIX timers, timerfds,
 * and waits for a signal. */
#include "calls_timers.h"
#include "common.h"
#include "contexts.h"

/* ---- ITIMER_REAL ---- */

const struct itimerval driver_spec = { { 0, PERIOD_NS / 1000 }, { 0, PERIOD_NS / 1000 } };

/* A timer armed for `armed` ns at t0 shows, at t1, no more than that and
 * no less than what is left by the clock, less what the call's unit
 * truncates (1 us for an itimerval, 1 ns for an itimerspec). */
static void left_check(struct ctx *c, long long left, long long armed, long long t0, long long t1, long long unit,
		       const char *what)
{
	if (left < 0 || left > armed || left <= armed - (t1 - t0) - unit)
		fail(c, what, 0);
}

void c_alarm(struct ctx *c)
{
	long long t0 = mono_ns();
	unsigned before = alarm(PROBE_NS / SEC);
	unsigned left = alarm(0);
	long long t1 = mono_ns();
	if (itimer_use == IT_SHARED) {
		check(c, before <= PROBE_NS / SEC && left <= PROBE_NS / SEC, "range");
		return;
	}
	check(c, before == 0, "was_armed");
	/* the kernel rounds what is left to the nearest second */
	long long least = (PROBE_NS - (t1 - t0) + SEC / 2) / SEC;
	check(c, left <= PROBE_NS / SEC && (long long)left >= least, "left");
}

void c_setitimer(struct ctx *c)
{
	struct itimerval old, cur;
	if (itimer_use == IT_DRIVER) {
		/* re-arm the driver, as a handler re-arming its own timer does */
		if (setitimer(ITIMER_REAL, &driver_spec, &old) != 0) {
			fail(c, "setitimer", errno);
			return;
		}
		check(c, tv_ns(old.it_interval) == PERIOD_NS, "interval");
		/* 0 while its SIGALRM is pending: Linux re-arms it as the signal
		 * is taken */
		check(c, tv_ns(old.it_value) >= 0 && tv_ns(old.it_value) <= PERIOD_NS, "value");
		return;
	}
	struct itimerval on = { { 0, 0 }, tv_of(PROBE_NS) }, off = { { 0, 0 }, { 0, 0 } };
	long long t0 = mono_ns();
	if (setitimer(ITIMER_REAL, &on, &old) != 0) {
		fail(c, "setitimer", errno);
		return;
	}
	int strict = itimer_use == IT_STRICT;
	if (strict)
		check(c, tv_ns(old.it_value) == 0 && tv_ns(old.it_interval) == 0, "was_armed");
	if (getitimer(ITIMER_REAL, &cur) != 0)
		fail(c, "getitimer", errno);
	else if (strict)
		left_check(c, tv_ns(cur.it_value), PROBE_NS, t0, mono_ns(), 1000, "left");
	if (setitimer(ITIMER_REAL, &off, &old) != 0)
		fail(c, "setitimer_off", errno);
	else if (strict)
		left_check(c, tv_ns(old.it_value), PROBE_NS, t0, mono_ns(), 1000, "left_at_disarm");
	else
		check(c, tv_ns(old.it_value) <= PROBE_NS && old.it_value.tv_usec < 1000000, "range");
}

void c_getitimer(struct ctx *c)
{
	struct itimerval cur;
	if (getitimer(ITIMER_REAL, &cur) != 0) {
		fail(c, "getitimer", errno);
		return;
	}
	if (itimer_use == IT_DRIVER) {
		check(c, tv_ns(cur.it_interval) == PERIOD_NS, "interval");
		check(c, tv_ns(cur.it_value) >= 0 && tv_ns(cur.it_value) <= PERIOD_NS, "value"); /* 0: see above */
	} else if (itimer_use == IT_STRICT) {
		check(c, tv_ns(cur.it_value) == 0 && tv_ns(cur.it_interval) == 0, "armed");
	} else {
		check(c, tv_ns(cur.it_value) <= PROBE_NS && cur.it_value.tv_usec < 1000000, "range");
	}
}

/* ---- POSIX timers ---- */

/* A timer of SIGEV_NONE on clk (each time a new one; every other time on
 * CLOCK_REALTIME): armed, read, its overruns, deleted. */
void c_timer_create(struct ctx *c)
{
	clockid_t clk = c->f->round % 2 ? CLOCK_REALTIME : CLOCK_MONOTONIC;
	struct sigevent ev = { .sigev_notify = SIGEV_NONE };
	timer_t t;
	if (timer_create(clk, &ev, &t) != 0) {
		fail(c, "timer_create", errno);
		return;
	}
	struct itimerspec on = { { 0, 0 }, ts_of(PROBE_NS) }, cur;
	long long t0 = mono_ns();
	if (timer_settime(t, 0, &on, NULL) != 0)
		fail(c, "timer_settime", errno);
	else if (timer_gettime(t, &cur) != 0)
		fail(c, "timer_gettime", errno);
	else
		left_check(c, ns_of(cur.it_value), PROBE_NS, t0, mono_ns(), 1, "left");
	check(c, timer_getoverrun(t) == 0, "overrun");
	if (timer_delete(t) != 0)
		fail(c, "timer_delete", errno);
}

void c_timer_settime(struct ctx *c)
{
	timer_t t = c->f->idle;
	struct itimerspec on = { { 0, 0 }, ts_of(PROBE_NS) }, off = { { 0, 0 }, { 0, 0 } }, old, cur;
	long long t0 = mono_ns();
	if (timer_settime(t, 0, &on, &old) != 0) {
		fail(c, "timer_settime", errno);
		return;
	}
	check(c, ns_of(old.it_value) == 0, "was_armed");
	if (timer_gettime(t, &cur) != 0)
		fail(c, "timer_gettime", errno);
	else
		left_check(c, ns_of(cur.it_value), PROBE_NS, t0, mono_ns(), 1, "left");
	if (timer_settime(t, 0, &off, &old) != 0)
		fail(c, "timer_settime_off", errno);
	else
		left_check(c, ns_of(old.it_value), PROBE_NS, t0, mono_ns(), 1, "left_at_disarm");
}

void c_timer_gettime(struct ctx *c)
{
	struct itimerspec cur;
	if (timer_gettime(c->f->armed, &cur) != 0) {
		fail(c, "timer_gettime", errno);
		return;
	}
	left_check(c, ns_of(cur.it_value), ARMED_NS, c->f->armed_at, mono_ns(), 1, "left");
	check(c, ns_of(cur.it_interval) == 0, "interval");
}

void c_timer_getoverrun(struct ctx *c)
{
	int n = timer_getoverrun(c->f->armed);
	if (n < 0)
		fail(c, "timer_getoverrun", errno);
	else
		check(c, n == 0, "overrun");
}

/* ---- timerfd ---- */

/* Reads a timerfd's expirations, restarting after a handler. */
static int tfd_read(struct ctx *c, int fd, uint64_t *n)
{
	while (read(fd, n, sizeof *n) != (ssize_t)sizeof *n) {
		if (errno != EINTR) {
			fail(c, "read", errno);
			return -1;
		}
		interrupted();
	}
	return 0;
}

/* create, settime (every other time absolute), gettime, read, close. */
void c_timerfd(struct ctx *c)
{
	int fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
	if (fd < 0) {
		fail(c, "timerfd_create", errno);
		return;
	}
	int absolute = c->f->round % 2;
	long long t0 = mono_ns();
	struct itimerspec on = { { 0, 0 }, ts_of(absolute ? t0 + SLEEP_NS : SLEEP_NS) }, cur;
	if (timerfd_settime(fd, absolute ? TFD_TIMER_ABSTIME : 0, &on, NULL) != 0) {
		fail(c, "timerfd_settime", errno);
		close(fd);
		return;
	}
	if (timerfd_gettime(fd, &cur) != 0) {
		fail(c, "timerfd_gettime", errno);
	} else {
		/* 0 only once it has expired */
		long long left = ns_of(cur.it_value);
		check(c, left <= SLEEP_NS && (left > 0 || mono_ns() - t0 >= SLEEP_NS), "left");
	}
	uint64_t n = 0;
	if (tfd_read(c, fd, &n) == 0) {
		check(c, n == 1, "expirations");
		waited(c, t0, mono_ns(), SLEEP_NS);
	}
	if (close(fd) != 0)
		fail(c, "close", errno);
}

void c_timerfd_gettime(struct ctx *c)
{
	struct itimerspec cur;
	if (timerfd_gettime(c->f->tfd_armed, &cur) != 0) {
		fail(c, "timerfd_gettime", errno);
		return;
	}
	left_check(c, ns_of(cur.it_value), ARMED_NS, c->f->tfd_armed_at, mono_ns(), 1, "left");
}

/* A blocking read of a timerfd ticking every SLEEP_NS: the timerfd loop. */
void c_timerfd_read(struct ctx *c)
{
	uint64_t n = 0;
	if (tfd_read(c, c->f->tfd_tick, &n) == 0)
		check(c, n >= 1, "expirations");
}

/* ---- waiting for a signal ---- */

static void arm_wake(struct ctx *c, long long interval)
{
	struct itimerspec on = { ts_of(interval), ts_of(WAKE_NS) };
	if (timer_settime(c->f->wake, 0, &on, NULL) != 0)
		fail(c, "timer_settime", errno);
}

/* Blocks the wake signal, arms it (or, every other time, raises it: it is
 * pending when sigsuspend starts) and sigsuspends until it has come. */
void c_sigsuspend(struct ctx *c)
{
	int sig = wake_sig(c->who), pending = c->f->round % 2;
	sigset_t block, old, during;
	sigemptyset(&block);
	sigaddset(&block, sig);
	pthread_sigmask(SIG_BLOCK, &block, &old);
	int seen = wakes[c->who];
	long long t0 = mono_ns();
	if (pending)
		raise(sig);
	else
		arm_wake(c, 0);
	during = old;
	sigdelset(&during, sig);
	while (wakes[c->who] == seen) {
		sigsuspend(&during);
		if (errno != EINTR)
			fail(c, "sigsuspend", errno);
	}
	if (!pending)
		waited(c, t0, mono_ns(), WAKE_NS);
	pthread_sigmask(SIG_SETMASK, &old, NULL);
}

/* pause() until the wake signal has come; the wake timer is periodic, so a
 * signal that came before pause began is followed by another. */
void c_pause(struct ctx *c)
{
	int seen = wakes[c->who];
	long long t0 = mono_ns();
	arm_wake(c, WAKE_NS);
	while (wakes[c->who] == seen)
		if (pause() != -1 || errno != EINTR)
			fail(c, "pause", errno);
	waited(c, t0, mono_ns(), WAKE_NS);
	struct itimerspec off = { { 0, 0 }, { 0, 0 } };
	timer_settime(c->f->wake, 0, &off, NULL);
}
