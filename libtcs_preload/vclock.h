/* The controller's virtual clock (vclock.c): virtual time now, read from
 * the clock page without a round trip; the CPU time charged so far; where
 * a request's charge ends. tcs_vnow() is inline: clock reads are hot. */
#ifndef TCS_PRELOAD_VCLOCK_H
#define TCS_PRELOAD_VCLOCK_H

#include <time.h>

#include "cpu_estimate.h"
#include "runtime.h"

/* v, or the latest virtual time already told if that is later (the
 * page's v_seen, which the coordinator reads too). Threads share one core,
 * so a plain load and store (no locked instruction) keep it. */
static inline int64_t tcs_v_not_before(int64_t v)
{
	int64_t *told = &tcs_rt.page->v_seen;
	int64_t seen = __atomic_load_n(told, __ATOMIC_RELAXED);
	if (v < seen)
		return seen;
	__atomic_store_n(told, v, __ATOMIC_RELAXED);
	return v;
}

/* The clock's two ways up into the waits above it, which start-up fills
 * (start.c): what a clock read does when the coordinator has stepped the
 * controller aside (TCS_PAGE_ASLEEP: asks the world's time, wait.c's
 * tcs_catch_up), and what a request's charge point does with a journal
 * (replay.c's tcs_replay_request: replaying, it reaches the record's time
 * first). Both wait, and a wait reads this clock: a call down through a
 * pointer rather than a file below calling one above. */
struct tcs_vclock_ways_up {
	void (*catch_up)(void);
	void (*journal_request)(unsigned type);
};
extern struct tcs_vclock_ways_up tcs_vclock_up TCS_HIDDEN;

/* The process CPU time up to which a request of type (TCS_MSG_*) charges
 * it. Replaying, the record's time for the request is reached first. */
int64_t tcs_charge_point(unsigned type) TCS_HIDDEN;
/* In a new child: the CPU readings it inherited are its parent's. */
void tcs_cpu_forget(void) TCS_HIDDEN;
/* The virtual CPU time charged to the controller so far. */
int64_t tcs_charged_now(void) TCS_HIDDEN;

/* Virtual origin of a clock usable for sleeping, or -EINVAL when id is not
 * such a clock (CPU-time and unknown clocks). */
int64_t tcs_sleep_clock_origin(clockid_t id) TCS_HIDDEN;

/* The controller's virtual time now. Stepped aside by the coordinator
 * (TCS_PAGE_ASLEEP), it first asks the world's time (tcs_catch_up,
 * wait.c, through tcs_vclock_up). */
static inline __attribute__((always_inline)) int64_t tcs_vnow(void)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	if (__builtin_expect(__atomic_load_n(&p->flags, __ATOMIC_RELAXED) & TCS_PAGE_ASLEEP, 0))
		tcs_vclock_up.catch_up();
	/* Lockstep needs no CPU reading: the cheapest path of all. */
	if (p->mode == TCS_MODE_LOCKSTEP)
		return tcs_page_lockstep_v(p, tcs_page_read_slice(p));
#if defined(__x86_64__)
	/* While the anchor holds, so does the slice it was taken in (a new
	 * slice bumps gen): virtual time is the anchor's plus the TSC since,
	 * with no slice to read (cpu_estimate.c). */
	if (tcs_anchor.v_valid) {
		int64_t age = tcs_anchor_age(p, &tcs_anchor);
		if (age >= 0)
			return tcs_v_not_before(tcs_anchor.v + age);
	}
	uint32_t gen = __atomic_load_n(&p->gen, __ATOMIC_ACQUIRE);
#endif
	struct tcs_slice s = tcs_page_read_slice(p);
	int64_t v = tcs_page_vnow(p, s, tcs_process_cpu_estimate());
#if defined(__x86_64__)
	tcs_anchor_note_slice(p, s, gen);
#endif
	return tcs_v_not_before(v);
}

#endif
