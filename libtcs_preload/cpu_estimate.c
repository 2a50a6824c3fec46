/* The process's CPU time without a system call, for cpu-mode clock reads.
 *
 * Reading CLOCK_PROCESS_CPUTIME_ID is a system call (~240 ns here, 12x a
 * native vDSO clock read). Where the coordinator pins a controller to one
 * core under SCHED_FIFO (TCS_PAGE_CPU_ESTIMATE) and it has one thread, it
 * uses CPU at exactly the rate the TSC advances, except while the
 * coordinator runs on that core (it bumps the page's gen each time, and with
 * each new slice) or while the process sleeps in the kernel outside tcs's
 * hooks. So each thread
 * keeps an anchor — a real reading and the TSC at that moment — and
 * extrapolates from it with the TSC, taking a real reading again when gen
 * changed or the anchor is older than tsc_resync ticks (20 us). An estimate
 * may be above the truth (the process slept in the kernel, or was
 * throttled) or below it (an interrupt taken between the reading and the
 * TSC read is charged to the process), by a few microseconds at most. Clock
 * reads use it, which tcs_vnow() keeps from going back; so does a request's
 * claim of where its charge ends, which the coordinator takes only when
 * plausible (Coordinator::charge_point), and an estimate too high there is
 * made good by the next slice, which starts from it. */
#include "preload.h"

#if defined(__x86_64__)

__thread struct tcs_anchor tcs_anchor;

int64_t tcs_process_cpu_resync(void)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	struct tcs_anchor *a = &tcs_anchor;
	if (!(p->flags & TCS_PAGE_CPU_ESTIMATE) || a->busy ||
	    __atomic_load_n(&p->threads_started, __ATOMIC_RELAXED) != 0) /* no longer FIFO */
		return tcs_process_cpu();
	/* gen read before the real reading: a coordinator run after it makes
	 * the next read take a real reading again. */
	uint32_t gen = __atomic_load_n(&p->gen, __ATOMIC_ACQUIRE);
	a->busy = 1;
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	int64_t cpu = tcs_process_cpu();
	uint64_t after = __rdtsc();
	if (cpu >= 0) {
		a->tsc = after;
		a->cpu = cpu;
		a->gen = gen;
		a->valid = 1;
	}
	a->v_valid = 0;
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	a->busy = 0;
	return cpu;
}

/* Clock reads in cpu mode go faster still when the anchor also knows the
 * virtual time it stands for: then a read is the TSC, one multiplication
 * and no slice (tcs_vnow). Known once a read has seen the slice in force
 * when the anchor was taken: gen the same before the slice was read, when
 * the anchor was taken and now (the coordinator bumps gen before it writes
 * a slice); at the usual scale of 1, and with the anchor past the slice's
 * start, so that virtual time grows with the TSC from there on. */
void tcs_anchor_note_slice(const struct tcs_clock_page *p, struct tcs_slice s, uint32_t gen)
{
	struct tcs_anchor *a = &tcs_anchor;
	if (!a->valid || a->v_valid || a->busy || p->cpu_scale != 1.0 || a->gen != gen ||
	    __atomic_load_n(&p->gen, __ATOMIC_ACQUIRE) != gen)
		return;
	int64_t exit_cpu = __atomic_load_n(&p->exit_cpu, __ATOMIC_RELAXED);
	int64_t from = exit_cpu > s.cpu_base ? exit_cpu : s.cpu_base;
	if (a->cpu < from)
		return;
	a->busy = 1;
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	a->v = tcs_ns_add(s.v_base, a->cpu - from);
	a->v_valid = 1;
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	a->busy = 0;
}

#endif
