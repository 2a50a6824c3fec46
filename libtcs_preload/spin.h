/* Spins in lockstep (spin.c): a loop that waits by reading the clock, or
 * by reading a device or polling that has nothing yet, makes no wait, and
 * in lockstep only waits move virtual time. So each such call made without
 * a wait since the last one costs what it costs natively (the clock page's
 * spin_clock_ns, spin_read_ns), and the spin ends where it would on the
 * machine. In cpu mode the spin's CPU is charged: nothing to do here. */
#ifndef TCS_PRELOAD_SPIN_H
#define TCS_PRELOAD_SPIN_H

#include "roundtrip.h"
#include "thread_waits.h"
#include "vclock.h"

/* Virtual time now for a clock the program reads: in lockstep, later by
 * the read's cost when it spins. */
int64_t tcs_spin_clock_read(void) TCS_HIDDEN;

static inline int64_t tcs_program_vnow(void)
{
	if (__builtin_expect(tcs_calls != NULL, 0))
		tcs_settle_for_clock();
	if (tcs_rt.page->mode != TCS_MODE_LOCKSTEP)
		return tcs_vnow();
	return tcs_spin_clock_read();
}

/* Virtual time now for a timer the program reads (getitimer,
 * timer_gettime, timerfd_gettime): what is left of a timer is a clock, so
 * a loop that reads one spins as clock reads do. (Replaying, the record
 * has no entry for such a read: it costs nothing.) */
static inline int64_t tcs_timer_read_vnow(void)
{
	if (__atomic_load_n(&tcs_rt.page->flags, __ATOMIC_RELAXED) & TCS_PAGE_REPLAY)
		return tcs_vnow();
	return tcs_program_vnow();
}

/* An empty non-blocking read or poll (lockstep: costs as it spins). held:
 * the caller is inside a hook's wait (tcs_wait_enter). */
void tcs_spin_empty_read(int held) TCS_HIDDEN;

/* Lockstep: virtual time v reached by computing (a spin's cost, a replayed
 * record's time): stored in the page, or, past its spin_limit, asked for
 * with a wait of its own that ends there. Returns virtual time after. held:
 * the caller is inside a hook's wait. */
int64_t tcs_spin_to(int64_t v, int held) TCS_HIDDEN;


#endif
