/* The process's CPU time (cpu_estimate.c): read from the kernel, or on
 * x86-64 estimated without a system call from a per-thread anchor and the
 * TSC. The estimate is inline: clock reads are hot. */
#ifndef TCS_PRELOAD_CPU_ESTIMATE_H
#define TCS_PRELOAD_CPU_ESTIMATE_H

#include <time.h>

#include "real.h"
#include "runtime.h"

/* A clock read straight from the kernel, in ns; -errno on failure. */
int64_t tcs_kernel_clock(clockid_t id) TCS_HIDDEN;
/* The process's real CPU time in ns (all threads). */
int64_t tcs_process_cpu(void) TCS_HIDDEN;
/* Every CPU-clock reading computes ns longer: the test suite's slow-clock
 * setup (TCS_CPU_CLOCK_DELAY_NS, read at start-up). */
void tcs_cpu_clock_delay_set(int64_t ns) TCS_HIDDEN;

#if defined(__x86_64__)
#include <x86intrin.h>
struct tcs_anchor {
	uint64_t tsc; /* when cpu was read, in ticks (tcs_ticks) */
	int64_t cpu;
	int64_t v;    /* v_valid: virtual time when cpu was read */
	uint32_t gen; /* the page's gen then */
	uint8_t valid;
	uint8_t v_valid;
	uint8_t busy; /* being rewritten: a signal handler must not use it */
};
extern __thread struct tcs_anchor tcs_anchor TCS_HIDDEN __attribute__((tls_model("initial-exec")));
/* A real reading, taken as the new anchor: the CPU at the end of the
 * reading. own: the reading is the runtime's own cost between hooks (a clock
 * read's), not charged (the page's own_cpu); else a hook's exit mark, which
 * excludes it by itself. */
int64_t tcs_process_cpu_resync(int own) TCS_HIDDEN;
/* Virtual time at the anchor, for the next reads (see tcs_vnow): s is the
 * slice read while the page's gen was gen. */
void tcs_anchor_note_slice(const struct tcs_clock_page *p, struct tcs_slice s, uint32_t gen) TCS_HIDDEN;
/* The estimate's clock: the TSC, or where it cannot serve the vDSO's
 * CLOCK_MONOTONIC_RAW in ns (TCS_PAGE_TICKS_VDSO). */
static inline uint64_t tcs_ticks(const struct tcs_clock_page *p)
{
	if (__builtin_expect(p->flags & TCS_PAGE_TICKS_VDSO, 0)) {
		struct timespec ts;
		tcs_real_fns.clock_gettime(CLOCK_MONOTONIC_RAW, &ts);
		return (uint64_t)tcs_ts_to_ns(&ts);
	}
	return __rdtsc();
}
/* ns in dt ticks. */
static inline int64_t tcs_ticks_ns(const struct tcs_clock_page *p, uint64_t dt)
{
	return (int64_t)(((unsigned __int128)dt * p->tick_mult) >> 32);
}
/* The CPU time since the anchor was taken, by the ticks; -1 if it no longer
 * holds (the coordinator ran since, it is older than tick_resync, or a
 * signal handler interrupted its rewrite). */
static inline int64_t tcs_anchor_age(const struct tcs_clock_page *p, const struct tcs_anchor *a)
{
	uint64_t now = tcs_ticks(p);
	if (!a->valid || a->busy || __atomic_load_n(&p->gen, __ATOMIC_ACQUIRE) != a->gen || now - a->tsc >= p->tick_resync)
		return -1;
	return tcs_ticks_ns(p, now - a->tsc);
}
static inline int64_t tcs_process_cpu_estimate(void)
{
	int64_t age = tcs_anchor_age(tcs_rt.page, &tcs_anchor);
	return age >= 0 ? tcs_anchor.cpu + age : tcs_process_cpu_resync(1);
}
/* The CPU at a hook's return, which later estimates start from while
 * nothing else ran on the core (the next request's charge point then needs
 * no system call of its own); claim: the request's charge point, or 0.
 * Exact in cpu mode; in lockstep mostly learnt (cpu_estimate.c). */
int64_t tcs_exit_mark(int64_t claim) TCS_HIDDEN;
static inline void tcs_anchor_forget_v(void)
{
	tcs_anchor.v_valid = 0;
}
#else
static inline int64_t tcs_process_cpu_estimate(void)
{
	return tcs_process_cpu();
}
static inline int64_t tcs_exit_mark(int64_t claim)
{
	(void)claim;
	return tcs_process_cpu();
}
static inline void tcs_anchor_forget_v(void)
{
}
#endif

#endif
