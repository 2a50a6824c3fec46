/* The idioms program's calls on clocks, sleeps and multiplexers. */
#include "calls_time.h"
#include "common.h"
#include "contexts.h"

/* ---- clocks: each read is no less than what that clock showed before it
 * started (time never goes backwards, whoever read it last) ---- */

static void clock_check(struct ctx *c, clockid_t id, long long *seen)
{
	long long before = __atomic_load_n(seen, __ATOMIC_SEQ_CST);
	struct timespec ts;
	if (clock_gettime(id, &ts) != 0) {
		fail(c, "clock_gettime", errno);
		return;
	}
	check(c, ts.tv_nsec >= 0 && ts.tv_nsec < SEC, "nsec_range");
	check(c, ns_of(ts) >= before, "went_back");
	at_most(seen, ns_of(ts));
}

void c_clock_mono(struct ctx *c)
{
	clock_check(c, CLOCK_MONOTONIC, &seen_mono);
}

void c_clock_real(struct ctx *c)
{
	clock_check(c, CLOCK_REALTIME, &seen_real);
}

void c_clock_process(struct ctx *c)
{
	clock_check(c, CLOCK_PROCESS_CPUTIME_ID, &seen_process);
}

void c_clock_thread(struct ctx *c)
{
	clock_check(c, CLOCK_THREAD_CPUTIME_ID, &seen_thread);
}

void c_gettimeofday(struct ctx *c)
{
	long long before = __atomic_load_n(&seen_real, __ATOMIC_SEQ_CST);
	struct timeval tv;
	if (gettimeofday(&tv, NULL) != 0) {
		fail(c, "gettimeofday", errno);
		return;
	}
	check(c, tv.tv_usec >= 0 && tv.tv_usec < 1000000, "usec_range");
	/* whole microseconds of a clock seen to the nanosecond */
	check(c, tv_ns(tv) + 999 >= before, "went_back");
	at_most(&seen_real, tv_ns(tv));
}

void c_time(struct ctx *c)
{
	long long before = __atomic_load_n(&seen_real, __ATOMIC_SEQ_CST);
	time_t t = time(NULL);
	long long after = clock_read(CLOCK_REALTIME);
	check(c, t != (time_t)-1, "failed");
	check(c, (t + 1) * SEC > before - COARSE_LAG_NS, "went_back");
	check(c, t * SEC <= after, "ahead_of_realtime");
}

void c_timespec_get(struct ctx *c)
{
	long long before = __atomic_load_n(&seen_real, __ATOMIC_SEQ_CST);
	struct timespec ts;
	if (timespec_get(&ts, TIME_UTC) != TIME_UTC) {
		fail(c, "timespec_get", errno);
		return;
	}
	check(c, ns_of(ts) >= before, "went_back");
	at_most(&seen_real, ns_of(ts));
}

void c_clock(struct ctx *c)
{
	long long before = __atomic_load_n(&seen_clock, __ATOMIC_SEQ_CST);
	clock_t v = clock();
	check(c, v != (clock_t)-1, "failed");
	check(c, (long long)v >= before, "went_back");
	at_most(&seen_clock, v);
}

void c_times(struct ctx *c)
{
	long long before = __atomic_load_n(&seen_times, __ATOMIC_SEQ_CST);
	long long before_cpu = __atomic_load_n(&seen_times_cpu, __ATOMIC_SEQ_CST);
	struct tms t;
	clock_t v = times(&t);
	if (v == (clock_t)-1) {
		fail(c, "times", errno);
		return;
	}
	check(c, (long long)v >= before, "went_back");
	check(c, (long long)(t.tms_utime + t.tms_stime) >= before_cpu, "cpu_went_back");
	at_most(&seen_times, v);
	at_most(&seen_times_cpu, t.tms_utime + t.tms_stime);
}

void c_getrusage(struct ctx *c)
{
	long long before = __atomic_load_n(&seen_rusage, __ATOMIC_SEQ_CST);
	struct rusage ru;
	if (getrusage(RUSAGE_SELF, &ru) != 0) {
		fail(c, "getrusage", errno);
		return;
	}
	long long cpu = tv_ns(ru.ru_utime) + tv_ns(ru.ru_stime);
	check(c, cpu >= before, "cpu_went_back");
	at_most(&seen_rusage, cpu);
}

/* ---- sleeps: never early, restarted with what is left ---- */

void c_nanosleep(struct ctx *c)
{
	struct timespec req = ts_of(SLEEP_NS), rem;
	long long t0 = mono_ns();
	while (nanosleep(&req, &rem) != 0) {
		if (errno != EINTR) {
			fail(c, "nanosleep", errno);
			return;
		}
		interrupted();
		req = rem;
	}
	waited(c, t0, mono_ns(), SLEEP_NS);
}

void c_clock_nanosleep(struct ctx *c)
{
	struct timespec req = ts_of(SLEEP_NS), rem;
	long long t0 = mono_ns();
	int e;
	while ((e = clock_nanosleep(CLOCK_MONOTONIC, 0, &req, &rem)) != 0) {
		if (e != EINTR) {
			fail(c, "clock_nanosleep", e);
			return;
		}
		interrupted();
		req = rem;
	}
	waited(c, t0, mono_ns(), SLEEP_NS);
}

/* TIMER_ABSTIME on CLOCK_MONOTONIC, every other time CLOCK_REALTIME: it
 * ends no earlier than its deadline on its own clock. */
void c_clock_nanosleep_abs(struct ctx *c)
{
	clockid_t clk = c->f->round % 2 ? CLOCK_REALTIME : CLOCK_MONOTONIC;
	long long t0 = mono_ns();
	long long deadline = clock_read(clk) + SLEEP_NS;
	struct timespec at = ts_of(deadline);
	int e;
	while ((e = clock_nanosleep(clk, TIMER_ABSTIME, &at, NULL)) != 0) {
		if (e != EINTR) {
			fail(c, "clock_nanosleep", e);
			return;
		}
		interrupted();
	}
	check(c, clock_read(clk) >= deadline, "before_deadline");
	waited(c, t0, mono_ns(), SLEEP_NS);
}

void c_usleep(struct ctx *c)
{
	long long t0 = mono_ns(), end = t0 + SLEEP_NS;
	useconds_t us = SLEEP_NS / 1000;
	while (usleep(us) != 0) {
		if (errno != EINTR) {
			fail(c, "usleep", errno);
			return;
		}
		interrupted();
		long long left = end - mono_ns();
		if (left <= 0)
			break;
		us = (left + 999) / 1000;
	}
	waited(c, t0, mono_ns(), SLEEP_NS);
}

void c_sleep(struct ctx *c)
{
	/* sleep(0): whole seconds would make a run take 20 s natively */
	check(c, sleep(0) == 0, "not_zero");
}

void c_thrd_sleep(struct ctx *c)
{
	struct timespec req = ts_of(SLEEP_NS), rem;
	long long t0 = mono_ns();
	int r;
	while ((r = thrd_sleep(&req, &rem)) != 0) {
		if (r != -1) {
			fail(c, "thrd_sleep", errno);
			return;
		}
		interrupted();
		req = rem;
	}
	waited(c, t0, mono_ns(), SLEEP_NS);
}

/* ---- multiplexers: wait on an empty pipe until the timeout ---- */

/* What is left of a wait until end, in whole ms rounded up (poll, epoll). */
/* The whole milliseconds left till end, rounded up (never early); the
 * wait so restarted may end as late as *asked, which this moves on. */
static int left_ms(long long end, long long *asked)
{
	long long now = mono_ns(), left = end - now;
	int ms = left <= 0 ? 0 : (int)((left + MS - 1) / MS);
	if (now + ms * MS > *asked)
		*asked = now + ms * MS;
	return ms;
}

void c_select(struct ctx *c)
{
	/* Linux's select leaves in tv what is left, in whole microseconds
	 * (fs/select.c truncates): a restart passes it on, and so may end
	 * up to 1 us sooner per interruption than the first call asked. */
	struct timeval tv = tv_of(SLEEP_NS);
	long long t0 = mono_ns(), restarts = 0;
	int r;
	for (;;) {
		fd_set rd;
		FD_ZERO(&rd);
		FD_SET(c->f->pipe_r, &rd);
		if ((r = select(c->f->pipe_r + 1, &rd, NULL, NULL, &tv)) >= 0 || errno != EINTR)
			break;
		interrupted();
		restarts++;
	}
	if (r != 0)
		fail(c, r < 0 ? "select" : "readable", r < 0 ? errno : 0);
	waited(c, t0, mono_ns(), SLEEP_NS - restarts * 1000);
}

void c_pselect(struct ctx *c)
{
	long long t0 = mono_ns(), end = t0 + SLEEP_NS;
	int r;
	for (;;) {
		fd_set rd;
		FD_ZERO(&rd);
		FD_SET(c->f->pipe_r, &rd);
		long long left = end - mono_ns();
		struct timespec ts = ts_of(left > 0 ? left : 0);
		if ((r = pselect(c->f->pipe_r + 1, &rd, NULL, NULL, &ts, NULL)) >= 0 || errno != EINTR)
			break;
		interrupted();
	}
	if (r != 0)
		fail(c, r < 0 ? "pselect" : "readable", r < 0 ? errno : 0);
	waited(c, t0, mono_ns(), SLEEP_NS);
}

void c_poll(struct ctx *c)
{
	long long t0 = mono_ns(), end = t0 + POLL_MS * MS, asked = end;
	int ms = POLL_MS, r;
	for (;;) {
		struct pollfd p = { .fd = c->f->pipe_r, .events = POLLIN };
		if ((r = poll(&p, 1, ms)) >= 0 || errno != EINTR)
			break;
		interrupted();
		ms = left_ms(end, &asked);
	}
	if (r != 0)
		fail(c, r < 0 ? "poll" : "readable", r < 0 ? errno : 0);
	waited_asked(c, t0, mono_ns(), POLL_MS * MS, asked - t0);
}

void c_ppoll(struct ctx *c)
{
	long long t0 = mono_ns(), end = t0 + SLEEP_NS;
	int r;
	for (;;) {
		struct pollfd p = { .fd = c->f->pipe_r, .events = POLLIN };
		long long left = end - mono_ns();
		struct timespec ts = ts_of(left > 0 ? left : 0);
		if ((r = ppoll(&p, 1, &ts, NULL)) >= 0 || errno != EINTR)
			break;
		interrupted();
	}
	if (r != 0)
		fail(c, r < 0 ? "ppoll" : "readable", r < 0 ? errno : 0);
	waited(c, t0, mono_ns(), SLEEP_NS);
}

void c_epoll_wait(struct ctx *c)
{
	long long t0 = mono_ns(), end = t0 + POLL_MS * MS, asked = end;
	int ms = POLL_MS, r;
	struct epoll_event ev;
	while ((r = epoll_wait(c->f->epfd, &ev, 1, ms)) < 0 && errno == EINTR) {
		interrupted();
		ms = left_ms(end, &asked);
	}
	if (r != 0)
		fail(c, r < 0 ? "epoll_wait" : "readable", r < 0 ? errno : 0);
	waited_asked(c, t0, mono_ns(), POLL_MS * MS, asked - t0);
}

/* epoll_pwait (ms), every other time epoll_pwait2 (a timespec). */
void c_epoll_pwait(struct ctx *c)
{
	int two = c->f->round % 2;
	long long want = two ? SLEEP_NS : POLL_MS * MS;
	long long t0 = mono_ns(), end = t0 + want, asked = end;
	int r;
	struct epoll_event ev;
	for (;;) {
		if (two) {
			long long left = end - mono_ns();
			struct timespec ts = ts_of(left > 0 ? left : 0);
			r = epoll_pwait2(c->f->epfd, &ev, 1, &ts, NULL);
		} else {
			r = epoll_pwait(c->f->epfd, &ev, 1, left_ms(end, &asked), NULL);
		}
		if (r >= 0 || errno != EINTR)
			break;
		interrupted();
	}
	if (r != 0)
		fail(c, r < 0 ? "epoll_pwait" : "readable", r < 0 ? errno : 0);
	waited_asked(c, t0, mono_ns(), want, asked - t0);
}
