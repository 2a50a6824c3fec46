/* The process's CPU time: read from the kernel, and without a system call,
 * for cpu-mode clock reads.
 *
 * Reading CLOCK_PROCESS_CPUTIME_ID is a system call (240 ns on one machine,
 * 1.35 us on another: 10x to 50x a native vDSO clock read). Where the
 * coordinator pins a controller to one core under SCHED_FIFO
 * (TCS_PAGE_CPU_ESTIMATE) and it has one thread, it uses CPU at exactly the
 * rate wall time passes, except while the coordinator runs on that core (it
 * bumps the page's gen each time, and with each new slice) or while the
 * process sleeps in the kernel outside tcs's hooks. So each thread keeps an
 * anchor — a real reading and the ticks of a cheap wall clock at that moment
 * (the TSC where the CPU says it is invariant, else the vDSO's
 * CLOCK_MONOTONIC_RAW: coordinator/realtime.cc chooses) — and extrapolates
 * from it, taking a real reading again when gen changed or the anchor is
 * older than tick_resync ticks (20 us). An estimate may be above the truth
 * (the process slept in the kernel, or was throttled) or below it (an
 * interrupt taken between the reading and the tick read is charged to the
 * process), by a few microseconds at most. Clock reads use it, which
 * tcs_vnow() keeps from going back; so does a request's claim of where its
 * charge ends, which the coordinator takes only when plausible
 * (Coordinator::charge_point), and an estimate too high there is made good
 * by the next slice, which starts from it. */
#include "cpu_estimate.h"
#include "raw_syscall.h"

int64_t tcs_kernel_clock(clockid_t id)
{
	struct timespec ts;
	long r = tcs_sys2(SYS_clock_gettime, id, &ts);
	return r < 0 ? r : tcs_ts_to_ns(&ts);
}

/* A machine whose CPU-clock system call is slow, imitated for the test
 * suite's slow-clock setup (TCS_CPU_CLOCK_DELAY_NS, read at start-up): each
 * reading computes that much longer, half before the kernel reads the clock
 * and half after, as the system call's own entry and exit would. */
static int64_t tcs_cpu_clock_delay;

void tcs_cpu_clock_delay_set(int64_t ns)
{
	tcs_cpu_clock_delay = ns;
}

static void tcs_compute_for(int64_t ns)
{
	int64_t until = tcs_kernel_clock(CLOCK_MONOTONIC) + ns;
	while (tcs_kernel_clock(CLOCK_MONOTONIC) < until)
		tcs_cpu_relax();
}

int64_t tcs_process_cpu(void)
{
	if (__builtin_expect(tcs_cpu_clock_delay == 0, 1))
		return tcs_kernel_clock(CLOCK_PROCESS_CPUTIME_ID);
	tcs_compute_for(tcs_cpu_clock_delay / 2);
	int64_t cpu = tcs_kernel_clock(CLOCK_PROCESS_CPUTIME_ID);
	tcs_compute_for(tcs_cpu_clock_delay - tcs_cpu_clock_delay / 2);
	return cpu;
}

#if defined(__x86_64__)

__thread struct tcs_anchor tcs_anchor;

/* Rewrites the anchor (busy meanwhile: a signal handler's read must not
 * see half of it); it stands for no virtual time until a read notes one. */
static void tcs_anchor_set(struct tcs_anchor *a, uint64_t ticks, int64_t cpu, uint32_t gen)
{
	a->busy = 1;
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	a->tsc = ticks;
	a->cpu = cpu;
	a->gen = gen;
	a->valid = 1;
	a->v_valid = 0;
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	a->busy = 0;
}

/* The least of the last 8 samples of a cost: a sample is late by any
 * interrupt or pause of the machine within it, never early. */
#define TCS_COST_SAMPLES 8
struct tcs_least_cost {
	int64_t v[TCS_COST_SAMPLES];
	unsigned n;
};

static void tcs_cost_note(struct tcs_least_cost *c, int64_t sample)
{
	c->v[c->n++ % TCS_COST_SAMPLES] = sample > 0 ? sample : 0;
}

/* The least sample held; -1 until there are at least `needed`. */
static int64_t tcs_cost_least(const struct tcs_least_cost *c, unsigned needed)
{
	if (c->n < needed || c->n == 0)
		return -1;
	unsigned held = c->n < TCS_COST_SAMPLES ? c->n : TCS_COST_SAMPLES;
	int64_t least = c->v[0];
	for (unsigned i = 1; i < held; i++)
		if (c->v[i] < least)
			least = c->v[i];
	return least;
}

/* What a real reading of the CPU clock costs (wall time, ticks). */
static struct tcs_least_cost tcs_reading_costs;

int64_t tcs_process_cpu_resync(int own)
{
	struct tcs_clock_page *p = tcs_rt.page;
	struct tcs_anchor *a = &tcs_anchor;
	if (!(p->flags & TCS_PAGE_CPU_ESTIMATE) || a->busy ||
	    __atomic_load_n(&p->threads_started, __ATOMIC_RELAXED) != 0) /* no longer FIFO */
		return tcs_process_cpu();
	/* gen read before the real reading: a coordinator run after it makes
	 * the next read take a real reading again. */
	uint32_t gen = __atomic_load_n(&p->gen, __ATOMIC_ACQUIRE);
	a->busy = 1; /* (the reading below is no anchor yet for a handler's read) */
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	uint64_t before = tcs_ticks(p);
	int64_t cpu = tcs_process_cpu();
	uint64_t after = tcs_ticks(p);
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	a->busy = 0;
	if (cpu < 0)
		return cpu;
	/* The kernel read the clock about halfway through the call: the CPU
	 * at its end is later by half of what the call took. The whole call
	 * is the runtime's own (unless the coordinator ran meanwhile, which
	 * the stale gen makes the next read redo), but credited as such no
	 * more than the least a reading costs: the ticks are wall time, and a
	 * pause of this core within the call (the host running another vCPU,
	 * an interrupt not charged to us) is not CPU of ours, and the
	 * program's CPU must never go back as the coordinator sees it. A call
	 * the coordinator ran within (gen moved: it was stopped, or shared
	 * its core) is no sample of a reading's cost. */
	int64_t took = tcs_ticks_ns(p, after - before);
	const int undisturbed = __atomic_load_n(&p->gen, __ATOMIC_ACQUIRE) == gen;
	if (undisturbed)
		tcs_cost_note(&tcs_reading_costs, took);
	int64_t least = tcs_cost_least(&tcs_reading_costs, 1);
	if (least < 0)
		least = 0; /* (none yet: the CPU as read, short by half a call) */
	if (took > least)
		took = least;
	cpu = tcs_ns_add(cpu, took / 2);
	if (own && undisturbed)
		__atomic_store_n(&p->own_cpu, tcs_ns_add(__atomic_load_n(&p->own_cpu, __ATOMIC_RELAXED), took),
				 __ATOMIC_RELAXED);
	tcs_anchor_set(a, after, cpu, gen);
	return cpu;
}

/* In lockstep the CPU feeds only the charged-CPU figures and CPU-time
 * clocks, never virtual time, and a hook's exit mark need not cost a system
 * call on every round trip (the one a CPU-clock read is; a lockstep round
 * trip needs none otherwise): it is the request's own claim plus what this
 * process's hooks have cost from their claim to their return, the least of
 * the last 8 real readings (a reading is late by any interrupt or pause, a
 * claim may be stale at a program's start: never early), which every 64th
 * mark takes again to stay true. A mark too early charges the next slice
 * more, and the next real one makes it good; too late, the coordinator
 * charges the claims short of it nothing until they pass it
 * (Coordinator::charge_point): either way no system call. */
static struct tcs_least_cost tcs_hook_costs;
static unsigned tcs_hook_marks;

int64_t tcs_exit_mark(int64_t claim)
{
	struct tcs_clock_page *p = tcs_rt.page;
	struct tcs_anchor *a = &tcs_anchor;
	if (p->mode != TCS_MODE_LOCKSTEP || claim <= 0 || !(p->flags & TCS_PAGE_CPU_ESTIMATE))
		return tcs_process_cpu_resync(0);
	int64_t hook_cost = tcs_cost_least(&tcs_hook_costs, TCS_COST_SAMPLES);
	if (a->busy || hook_cost < 0 || tcs_hook_marks++ % 64 == 63) {
		uint64_t before = tcs_ticks(p);
		int64_t cpu = tcs_process_cpu_resync(0);
		/* The hook's cost up to the reading, not the reading's own: the
		 * learnt marks are taken without one. (None, when the claim ran
		 * ahead: an estimate over a time the process did not run.) */
		tcs_cost_note(&tcs_hook_costs, cpu - tcs_ticks_ns(p, tcs_ticks(p) - before) - claim);
		return cpu;
	}
	int64_t cpu = tcs_ns_add(claim, hook_cost);
	tcs_anchor_set(a, tcs_ticks(p), cpu, __atomic_load_n(&p->gen, __ATOMIC_ACQUIRE));
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
	a->v = tcs_ns_add(s.v_base, tcs_page_slice_cpu(p, s, a->cpu));
	a->v_valid = 1;
	__atomic_signal_fence(__ATOMIC_SEQ_CST);
	a->busy = 0;
}

#endif
