/* Time arithmetic shared by the preload and the coordinator: nanosecond
 * integers, saturating conversions from the C time structs, and the one
 * formula that turns a controller's CPU progress into virtual time.
 *
 * Everything here is header-only, allocation-free and async-signal-safe, so
 * the preload can use it inside hooks. Both sides must compute virtual time
 * with exactly the same operations, which is why the formula lives here. */
#ifndef TCS_VTIME_H
#define TCS_VTIME_H

#include <stdint.h>
#include <sys/time.h>
#include <time.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TCS_NS_PER_US 1000LL
#define TCS_NS_PER_MS 1000000LL
#define TCS_NS_PER_S 1000000000LL
/* A deadline that never comes (an infinite wait). */
#define TCS_NEVER INT64_MAX

/* 0 if ts is a valid timespec (non-negative seconds, 0 <= tv_nsec < 1e9). */
static inline int tcs_ts_valid(const struct timespec *ts)
{
	return ts->tv_sec >= 0 && ts->tv_nsec >= 0 && ts->tv_nsec < TCS_NS_PER_S;
}

/* Nanoseconds in ts, saturating at TCS_NEVER. ts must be valid. */
static inline int64_t tcs_ts_to_ns(const struct timespec *ts)
{
	if (ts->tv_sec > (TCS_NEVER - ts->tv_nsec) / TCS_NS_PER_S)
		return TCS_NEVER;
	return (int64_t)ts->tv_sec * TCS_NS_PER_S + ts->tv_nsec;
}

static inline struct timespec tcs_ns_to_ts(int64_t ns)
{
	struct timespec ts;
	ts.tv_sec = (time_t)(ns / TCS_NS_PER_S);
	ts.tv_nsec = (long)(ns % TCS_NS_PER_S);
	if (ts.tv_nsec < 0) {
		ts.tv_sec -= 1;
		ts.tv_nsec += TCS_NS_PER_S;
	}
	return ts;
}

static inline struct timeval tcs_ns_to_tv(int64_t ns)
{
	struct timespec ts = tcs_ns_to_ts(ns);
	struct timeval tv;
	tv.tv_sec = ts.tv_sec;
	tv.tv_usec = (suseconds_t)(ts.tv_nsec / TCS_NS_PER_US);
	return tv;
}

/* a + b for a, b >= 0, saturating at TCS_NEVER. */
static inline int64_t tcs_ns_add(int64_t a, int64_t b)
{
	if (b >= TCS_NEVER - a)
		return TCS_NEVER;
	return a + b;
}

/* Virtual nanoseconds for cpu_ns of real CPU at the given scale. Rounded
 * down; both sides call exactly this so that they agree to the nanosecond. */
static inline int64_t tcs_scale_cpu(int64_t cpu_ns, double scale)
{
	/* The usual scale, without the trip through floating point (every
	 * clock read in cpu mode comes here). Equal to the general case for
	 * any cpu_ns below 2^53 ns (104 days); past that, both sides still
	 * agree, as both take this path. */
	if (__builtin_expect(scale == 1.0, 1))
		return cpu_ns > 0 ? cpu_ns : 0;
	double v = (double)cpu_ns * scale;
	if (v >= 9.2e18)
		return TCS_NEVER;
	return v > 0 ? (int64_t)v : 0;
}

/* Real CPU consumed in the current slice: from the later of the slice's
 * start (set by the coordinator) and the controller's own mark (set when a
 * hook returns, so that the hook's cost is not charged), to now. Never
 * negative, whatever a misbehaving controller wrote as its mark. */
static inline int64_t tcs_slice_cpu(int64_t cpu_base, int64_t exit_cpu, int64_t cpu_now)
{
	int64_t from = exit_cpu > cpu_base ? exit_cpu : cpu_base;
	return cpu_now > from ? cpu_now - from : 0;
}

/* What of `used` (a slice's CPU) is the controller's own: less the CPU the
 * runtime spent reading the CPU clock for clock reads between hooks, own_now
 * - own_base (see the clock page's own_cpu). Within 0..used, whatever a
 * misbehaving controller wrote. */
static inline int64_t tcs_less_own(int64_t used, int64_t own_base, int64_t own_now)
{
	if (own_now <= own_base)
		return used;
	uint64_t own = (uint64_t)own_now - (uint64_t)own_base;
	return own >= (uint64_t)used ? 0 : used - (int64_t)own;
}

#ifdef __cplusplus
}
#endif
#endif
