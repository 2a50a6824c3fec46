/* Clock hooks: every way a program reads the time or its CPU usage,
 * answered from the clock page (no round trip; no syscall in lockstep mode
 * for the wall clocks). Runs in any context, including signal handlers:
 * reads only, no state of its own. */
#include <sys/resource.h>
#include <sys/times.h>

#include "cpu_estimate.h"
#include "replay.h"
#include "raw_syscall.h"
#include "real.h"
#include "spin.h"
#include "vclock.h"

/* <sys/timeb.h> is gone from glibc's headers; the ABI stays. */
struct tcs_timeb {
	time_t time;
	unsigned short millitm;
	short timezone;
	short dstflag;
};

#define TCS_USER_HZ 100 /* the kernel's fixed clock tick for times() */

/* Kernel encoding of CPU-time clock ids (clock_getcpuclockid and friends). */
#define TCS_CPUCLOCK_PERTHREAD 4
static inline long tcs_cpuclock_pid(clockid_t id)
{
	return ~(long)(id >> 3);
}

static int64_t tcs_thread_cpu_scaled(clockid_t id)
{
	int64_t ns;
	if (__builtin_expect(tcs_journal_replaying(), 0) && tcs_replay_clock(TCS_J_THREAD_CPU, &ns))
		return ns;
	ns = tcs_kernel_clock(id);
	ns = ns < 0 ? ns : tcs_scale_cpu(ns, tcs_rt.page->cpu_scale);
	if (__builtin_expect(tcs_journal_on(), 0) && ns >= 0)
		tcs_journal_note(TCS_J_THREAD_CPU, 0, ns, 0);
	return ns;
}

/* What the program's clock reads say, virtual time and CPU time: journalled
 * when recording, the record's when replaying (journal_write.h). */
static int64_t tcs_journalled(unsigned kind, int64_t (*live)(void))
{
	int64_t v;
	if (tcs_journal_replaying() && tcs_replay_clock(kind, &v))
		return v;
	v = live();
	tcs_journal_note(kind, 0, v, 0);
	return v;
}

static int64_t tcs_program_time(void)
{
	if (__builtin_expect(!tcs_journal_on(), 1))
		return tcs_program_vnow();
	return tcs_journalled(TCS_J_CLOCK, tcs_program_vnow);
}

static int64_t tcs_program_cpu(void)
{
	if (__builtin_expect(!tcs_journal_on(), 1))
		return tcs_charged_now();
	return tcs_journalled(TCS_J_CPU, tcs_charged_now);
}

/* The virtual value of clock id in *ns, or 1 when the clock is not one tcs
 * virtualises (the caller then asks the kernel). */
static int tcs_virtual_clock(clockid_t id, int64_t *ns)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	switch (id) {
	case CLOCK_REALTIME:
	case CLOCK_REALTIME_COARSE:
	case CLOCK_REALTIME_ALARM:
		*ns = p->real_origin_ns + tcs_program_time();
		return 0;
	case CLOCK_MONOTONIC:
	case CLOCK_MONOTONIC_RAW:
	case CLOCK_MONOTONIC_COARSE:
	case CLOCK_BOOTTIME:
	case CLOCK_BOOTTIME_ALARM:
		*ns = p->mono_origin_ns + tcs_program_time();
		return 0;
	case CLOCK_TAI:
		*ns = p->tai_origin_ns + tcs_program_time();
		return 0;
	case CLOCK_PROCESS_CPUTIME_ID:
		*ns = tcs_program_cpu();
		return 0;
	case CLOCK_THREAD_CPUTIME_ID:
		*ns = tcs_thread_cpu_scaled(id);
		return *ns < 0 ? 1 : 0;
	default:
		if (id >= 0)
			return 1;
		if (id & TCS_CPUCLOCK_PERTHREAD) {
			*ns = tcs_thread_cpu_scaled(id);
			return *ns < 0 ? 1 : 0;
		}
		if (tcs_cpuclock_pid(id) == 0 || tcs_cpuclock_pid(id) == tcs_rt.pid) {
			*ns = tcs_program_cpu();
			return 0;
		}
		return 1; /* another process's CPU clock, or a PTP device: real */
	}
}

/* Before start-up resolved it, the kernel's: a clock read (maybe in a
 * signal handler) never resolves anything itself (real.h). */
static int tcs_real_clock_gettime(clockid_t id, struct timespec *ts)
{
	int (*real)(clockid_t, struct timespec *) = __atomic_load_n(&tcs_real_fns.clock_gettime, __ATOMIC_RELAXED);
	if (real)
		return real(id, ts);
	return tcs_errno_result(tcs_sys2(SYS_clock_gettime, id, ts));
}

TCS_EXPORT int clock_gettime(clockid_t id, struct timespec *ts)
{
	/* The clock control loops read most, on the shortest path. */
	if (__builtin_expect(id == CLOCK_MONOTONIC, 1) && tcs_active()) {
		*ts = tcs_ns_to_ts(tcs_rt.page->mono_origin_ns + tcs_program_time());
		return 0;
	}
	int64_t ns;
	if (tcs_active() && tcs_virtual_clock(id, &ns) == 0) {
		*ts = tcs_ns_to_ts(ns);
		return 0;
	}
	return tcs_real_clock_gettime(id, ts);
}

static int64_t tcs_realtime_ns(void)
{
	int64_t ns;
	if (tcs_active() && tcs_virtual_clock(CLOCK_REALTIME, &ns) == 0)
		return ns;
	struct timespec ts;
	tcs_real_clock_gettime(CLOCK_REALTIME, &ts);
	return tcs_ts_to_ns(&ts);
}

TCS_EXPORT int gettimeofday(struct timeval *tv, void *tz)
{
	if (!tcs_active()) {
		int (*real)(struct timeval *, void *) = __atomic_load_n(&tcs_real_fns.gettimeofday, __ATOMIC_RELAXED);
		if (real)
			return real(tv, tz);
		return tcs_errno_result(tcs_sys2(SYS_gettimeofday, tv, tz));
	}
	if (tz)
		tcs_sys2(SYS_gettimeofday, NULL, tz);
	struct timeval *out = tv; /* glibc declares tv nonnull; the kernel allows NULL */
	if (out)
		*out = tcs_ns_to_tv(tcs_realtime_ns());
	return 0;
}

TCS_EXPORT time_t time(time_t *t)
{
	time_t now = (time_t)(tcs_realtime_ns() / TCS_NS_PER_S);
	if (t)
		*t = now;
	return now;
}

TCS_EXPORT int timespec_get(struct timespec *ts, int base)
{
	if (base != TIME_UTC)
		return 0;
	*ts = tcs_ns_to_ts(tcs_realtime_ns());
	return base;
}

/* (No public header declares it any more.) */
TCS_EXPORT int ftime(struct tcs_timeb *tb);
TCS_EXPORT int ftime(struct tcs_timeb *tb)
{
	int64_t ns = tcs_realtime_ns();
	tb->time = (time_t)(ns / TCS_NS_PER_S);
	tb->millitm = (unsigned short)(ns % TCS_NS_PER_S / TCS_NS_PER_MS);
	tb->timezone = 0;
	tb->dstflag = 0;
	return 0;
}

static int64_t tcs_process_cpu_ns(void)
{
	return tcs_active() ? tcs_program_cpu() : tcs_kernel_clock(CLOCK_PROCESS_CPUTIME_ID);
}

TCS_EXPORT clock_t clock(void)
{
	int64_t ns = tcs_process_cpu_ns();
	return ns < 0 ? (clock_t)-1 : (clock_t)(ns / (TCS_NS_PER_S / CLOCKS_PER_SEC));
}

TCS_EXPORT clock_t times(struct tms *buf)
{
	long r = tcs_sys1(SYS_times, buf);
	if (!tcs_active() || r < 0)
		return (clock_t)tcs_errno_result(r);
	if (buf) {
		buf->tms_utime = (clock_t)(tcs_program_cpu() / (TCS_NS_PER_S / TCS_USER_HZ));
		buf->tms_stime = 0;
	}
	return (clock_t)((tcs_rt.page->mono_origin_ns + tcs_program_time()) / (TCS_NS_PER_S / TCS_USER_HZ));
}

TCS_EXPORT int getrusage(int who, struct rusage *ru)
{
	long r = tcs_sys2(SYS_getrusage, who, ru);
	if (r < 0 || !tcs_active())
		return tcs_errno_result(r);
	int64_t ns = who == RUSAGE_SELF     ? tcs_program_cpu()
		     : who == RUSAGE_THREAD ? tcs_thread_cpu_scaled(CLOCK_THREAD_CPUTIME_ID)
					    : -1;
	if (ns >= 0) {
		ru->ru_utime = tcs_ns_to_tv(ns);
		ru->ru_stime = tcs_ns_to_tv(0);
	}
	return 0;
}
