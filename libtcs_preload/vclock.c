/* The controller's virtual clock (vclock.h): what it has been told, so
 * that no clock it reads goes back, and what a request charges. Runs in
 * any context, signal handlers included: no locks. */
#include "vclock.h"

#include "journal_write.h"


/* Until start-up fills them: nothing to catch up with, no journal. */
static void tcs_no_catch_up(void)
{
}

static void tcs_no_journal_request(unsigned type)
{
	(void)type;
}

struct tcs_vclock_ways_up tcs_vclock_up = { tcs_no_catch_up, tcs_no_journal_request };

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

int64_t tcs_charge_point(unsigned type)
{
	if (__builtin_expect(tcs_journal_on(), 0))
		tcs_vclock_up.journal_request(type);
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
