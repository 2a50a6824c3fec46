/* The idioms program's findings: the checks every call makes, kept with
 * atomics (handlers update them), and the clocks' highest readings. */
#include "calls_timers.h"
#include "common.h"

const char STATE[] = "/dev/tcs/pendulum/state";
const char TORQUE[] = "/dev/tcs/pendulum/torque";

struct flow flows[WHOS];

struct stats S = { .sleep_min = { -1, -1 }, .over_max = { -1, -1 }, .slack = -1 };

/* The largest value each clock has shown: a later read may not be less. */
long long seen_mono, seen_real, seen_process, seen_thread, seen_clock, seen_times, seen_times_cpu, seen_rusage;

/* Per wake signal: how many came, and the last one's si_code, si_pid and
 * si_value (to tell kill from raise from sigqueue). */
volatile int wakes[WHOS];
volatile int wake_code[WHOS], wake_pid[WHOS], wake_value[WHOS];

/* How ITIMER_REAL may be checked (idioms.h). */
int itimer_use = IT_STRICT;

long long sum(long long *p, long long n)
{
	return __atomic_add_fetch(p, n, __ATOMIC_SEQ_CST);
}

void at_most(long long *p, long long v)
{
	long long cur = __atomic_load_n(p, __ATOMIC_SEQ_CST);
	while (v > cur && !__atomic_compare_exchange_n(p, &cur, v, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST))
		;
}

void at_least(long long *p, long long v)
{
	long long cur = __atomic_load_n(p, __ATOMIC_SEQ_CST);
	while ((cur < 0 || v < cur) && !__atomic_compare_exchange_n(p, &cur, v, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST))
		;
}

long long ns_of(struct timespec t)
{
	return t.tv_sec * SEC + t.tv_nsec;
}

struct timespec ts_of(long long ns)
{
	return (struct timespec){ ns / SEC, ns % SEC };
}

struct timeval tv_of(long long ns)
{
	return (struct timeval){ ns / SEC, ns % SEC / 1000 };
}

long long tv_ns(struct timeval t)
{
	return t.tv_sec * SEC + t.tv_usec * 1000;
}

long long clock_read(clockid_t id)
{
	struct timespec ts = { 0, 0 };
	clock_gettime(id, &ts);
	return ns_of(ts);
}

long long mono_ns(void)
{
	return clock_read(CLOCK_MONOTONIC);
}

void fail_with(struct ctx *c, const char *what, int err, int value)
{
	sum(&S.failures, 1);
	if (__atomic_exchange_n(&S.first_set, 1, __ATOMIC_SEQ_CST) == 0) {
		S.first_call = c->name;
		S.first_what = what;
		S.first_errno = err;
		S.first_value = value;
		S.first_role = c->role;
	}
}

/* A check failed; err: the errno that says why, or 0. */
void fail(struct ctx *c, const char *what, int err)
{
	fail_with(c, what, err, 0);
}

void check(struct ctx *c, int ok, const char *what)
{
	if (!ok)
		fail(c, what, 0);
}

/* A wait that asked for `want` ns took t1 - t0: never less. Restarted
 * after a signal with a timeout in coarser units, rounded up, it asked in
 * all for `asked` ns: how late it ended counts from there. */
void waited_asked(struct ctx *c, long long t0, long long t1, long long want, long long asked)
{
	long long took = t1 - t0;
	sum(&S.sleeps[c->role], 1);
	at_least(&S.sleep_min[c->role], took);
	at_most(&S.sleep_max[c->role], took);
	at_most(&S.over_max[c->role], took - asked);
	if (took < want)
		fail(c, "ended_early", 0);
}

void waited(struct ctx *c, long long t0, long long t1, long long want)
{
	waited_asked(c, t0, t1, want, want);
}

void interrupted(void)
{
	sum(&S.eintr, 1);
}

int wake_sig(int who)
{
	return SIGRTMIN + who;
}
