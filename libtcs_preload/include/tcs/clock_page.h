/* The clock page: one shared-memory page per controller through which the
 * coordinator publishes that controller's virtual clock, so that clock reads
 * in the controller need no round trip (and, in lockstep mode, no syscall).
 *
 * Writers: the coordinator writes the slice fields under a seqlock, and only
 * while the controller is stopped or blocked in a hook; the controller writes
 * only its own single-word fields (exit_cpu and the statistics), each with
 * one atomic store. The coordinator never trusts what the controller wrote:
 * see tcs_slice_cpu(). Uses GCC __atomic builtins so that the same header
 * serves the C preload and the C++ coordinator. */
#ifndef TCS_CLOCK_PAGE_H
#define TCS_CLOCK_PAGE_H

#include <stdint.h>

#include "mailbox.h"
#include "vtime.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TCS_PAGE_MAGIC 0x70736374u /* "tcsp" */
#define TCS_PAGE_VERSION 15u
#define TCS_PAGE_SIZE 4096

enum tcs_mode {
	TCS_MODE_CPU = 0,      /* virtual time advances with the CPU consumed */
	TCS_MODE_LOCKSTEP = 1, /* computation is free; only waits advance time */
};

/* flags: an absolute wait whose deadline has already passed (a deadline
 * miss) goes to the coordinator, which answers at once, instead of returning
 * without a round trip: set when a trace is written, so it records each miss
 * with the time it happened. */
#define TCS_PAGE_REPORT_MISSES 1u
/* flags: the controller may estimate its CPU time between readings of its
 * CPU-time clock from a cheap wall clock, the TSC unless TCS_PAGE_TICKS_VDSO
 * (see libtcs_preload/cpu_estimate.c): set where it runs pinned under
 * SCHED_FIFO, so that it uses CPU at the rate wall time passes whenever the
 * coordinator (which bumps gen) is not running. */
#define TCS_PAGE_CPU_ESTIMATE 2u
/* flags: the coordinator shares the controller's core at a higher SCHED_FIFO
 * priority, so it has answered a request the coordinator can answer at once
 * by the time the controller's send returns: look for the reply before
 * waiting for it. */
#define TCS_PAGE_FIFO 4u
/* flags, set and cleared by the coordinator while the controller runs: it
 * was found asleep outside the hooks (reading a pipe, say) and stepped
 * aside while others went on. Awake again by itself, before it looks at
 * its clock or waits, it asks for the world's time: what woke it may have
 * been written then, never earlier. */
#define TCS_PAGE_ASLEEP 8u
/* flags: the estimate's ticks are the vDSO's CLOCK_MONOTONIC_RAW in ns, on
 * a machine whose TSC cannot serve (coordinator/realtime.cc). */
#define TCS_PAGE_TICKS_VDSO 16u
/* flags: the controller runs on the coordinator's core now (controllers run
 * on every core tcs may use, one on each; coordinator/lanes.cc). With
 * TCS_PAGE_FIFO: a request's answer the coordinator could give at once is
 * there as soon as it is sent. */
#define TCS_PAGE_SHARES_CORE 32u
/* flags: the controller runs on a core of its own, beside the coordinator
 * polling on its core: its main thread hands requests over the page's
 * mailbox (tcs/mailbox.h). */
#define TCS_PAGE_MAILBOX 64u
/* flags: with TCS_PAGE_MAILBOX, other controllers are queued behind this
 * one on its core (lockstep): a request through the mailbox is parked at
 * once rather than spun for, so that the next one has the core. */
#define TCS_PAGE_QUEUED 128u
/* flags: --replay: clock values and the times of requests come from the
 * journal, a record's, until the program departs from it (mode is
 * lockstep meanwhile: virtual time moves as the record says, and only so). */
#define TCS_PAGE_REPLAY 256u

/* The seqlock-protected part: where the current slice started. */
struct tcs_slice {
	int64_t v_base;       /* virtual ns at the start of the slice */
	int64_t cpu_base;     /* the process's real CPU ns at that moment */
	int64_t charged_base; /* virtual CPU ns charged before the slice */
	int64_t own_base;     /* the page's own_cpu at that moment, less what the
			       * coordinator left out since (a stop's cost) */
};

struct tcs_clock_page {
	/* Set once before the controller starts. */
	uint32_t magic;
	uint32_t version;
	uint32_t mode;
	uint32_t flags;         /* TCS_PAGE_* */
	double cpu_scale;
	int64_t mono_origin_ns; /* real CLOCK_MONOTONIC at V = 0 */
	int64_t real_origin_ns; /* CLOCK_REALTIME at V = 0: the epoch */
	int64_t tai_origin_ns;  /* CLOCK_TAI at V = 0 */
	uint64_t tick_mult;     /* TCS_PAGE_CPU_ESTIMATE: ns per tick, times 2^32 */
	uint64_t tick_resync;   /* ticks after which an estimate is read again */
	int64_t owner_pid;      /* the process this page is for: another one (a child
				 * after exec) must register before it runs */
	/* Lockstep: the virtual cost of a clock read, and of an empty
	 * non-blocking read or poll, made without a wait since the last such
	 * call (a spin: spin.c). */
	int32_t spin_clock_ns;
	int32_t spin_read_ns;
	/* --seed: this process's key to the seeded stream (tcs/random_stream.h);
	 * 0: the system's randomness is real. */
	uint64_t random_key;

	/* Coordinator-written under the seqlock. */
	uint32_t seq;
	uint32_t gen; /* bumped whenever the coordinator ran on the controller's core */
	struct tcs_slice slice;
	/* Signals the coordinator has sent the process (a timer's, due while it
	 * computed): one atomic add after each kill. A wait with its own mask
	 * says in its BLOCK how many it had seen when it looked for pending ones
	 * (TCS_BLOCK_SIGMASK). */
	uint64_t signals_raised;
	/* Lockstep: how far virtual time may go by spinning in this slice
	 * (spin_v) before the controller must ask: the next time the world,
	 * a timer or another thread needs it. */
	int64_t spin_limit;
	/* Set once: the journal's size after the device table (0: none). */
	uint64_t journal_bytes;

	/* Controller-written, one atomic store each. */
	int64_t exit_cpu;        /* process CPU when the last hook returned */
	uint64_t past_deadlines; /* absolute sleeps whose deadline had passed */
	uint64_t quick_returns;  /* waits that returned without a round trip */
	int64_t detached_pid;    /* last descendant told it runs in real time */
	uint64_t threads_started; /* pthread_create calls: non-zero, the coordinator
				   * looks at every thread before time passes */
	uint64_t lazy_handles;   /* lockstep: device handles (bit h) written without
				  * a round trip, whose records the coordinator takes
				  * at the next request (libtcs_preload/lazy_writes.c) */
	int64_t own_cpu;         /* the runtime's own CPU in clock reads that had to
				  * read the CPU clock between hooks (a system call,
				  * 50x a native clock read on some machines): not
				  * the program's, not charged (cpu_estimate.c) */
	int64_t fork_claim;      /* the claim of its request after a fork, vfork or
				  * spawn, stored before the request goes: a child
				  * that registers first starts no later, not at
				  * the CPU of the hook since (on_child,
				  * coordinator/children.cc) */
	int64_t spin_v;          /* lockstep: the virtual time spinning reached in
				  * this slice, short of spin_limit (spin.c) */
	uint64_t random_drawn;   /* --seed: blocks of its stream drawn so far (kept
				  * across exec, so the stream goes on) */
	int64_t v_seen;          /* cpu mode: the latest virtual time a clock read
				  * of it returned. An estimate of its CPU may run
				  * ahead of the exact reading, by the ticks between
				  * two readings (tick_resync) at most: a controller
				  * woken by what this one wrote is told no earlier
				  * time (coordinator/asleep.cc) */
	uint64_t unanswered;     /* each second of real time a thread has waited
				  * for an answer in a round trip: the coordinator
				  * looks for one it owes no answer (stuck.cc) */

	/* Both sides, by its own rules (tcs/mailbox.h). */
	struct tcs_mailbox mailbox __attribute__((aligned(64)));
};

#if defined(__cplusplus)
static_assert(sizeof(struct tcs_clock_page) <= TCS_PAGE_SIZE, "page too large");
static_assert(__builtin_offsetof(struct tcs_clock_page, seq) == 88, "layout changed: bump TCS_PAGE_VERSION");
#else
_Static_assert(sizeof(struct tcs_clock_page) <= TCS_PAGE_SIZE, "page too large");
_Static_assert(__builtin_offsetof(struct tcs_clock_page, seq) == 88, "layout changed: bump TCS_PAGE_VERSION");
#endif

static inline void tcs_cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
	__builtin_ia32_pause();
#elif defined(__aarch64__)
	__asm__ __volatile__("yield" ::: "memory");
#endif
}

/* Reader side: a consistent snapshot of the slice. Lock-free; retries only
 * while the coordinator is writing, which it does for a few nanoseconds. */
static inline struct tcs_slice tcs_page_read_slice(const struct tcs_clock_page *p)
{
	struct tcs_slice s;
	uint32_t s1, s2;
	for (;;) {
		s1 = __atomic_load_n(&p->seq, __ATOMIC_ACQUIRE);
		if (s1 & 1u) {
			tcs_cpu_relax();
			continue;
		}
		s.v_base = __atomic_load_n(&p->slice.v_base, __ATOMIC_RELAXED);
		s.cpu_base = __atomic_load_n(&p->slice.cpu_base, __ATOMIC_RELAXED);
		s.charged_base = __atomic_load_n(&p->slice.charged_base, __ATOMIC_RELAXED);
		s.own_base = __atomic_load_n(&p->slice.own_base, __ATOMIC_RELAXED);
		__atomic_thread_fence(__ATOMIC_ACQUIRE);
		s2 = __atomic_load_n(&p->seq, __ATOMIC_RELAXED);
		if (s1 == s2)
			return s;
	}
}

/* Writer side (the coordinator only). */
static inline void tcs_page_bump_gen(struct tcs_clock_page *p);
static inline void tcs_page_write_slice(struct tcs_clock_page *p, struct tcs_slice s)
{
	tcs_page_bump_gen(p);
	uint32_t seq = __atomic_load_n(&p->seq, __ATOMIC_RELAXED);
	__atomic_store_n(&p->seq, seq + 1, __ATOMIC_RELAXED);
	__atomic_thread_fence(__ATOMIC_RELEASE);
	__atomic_store_n(&p->slice.v_base, s.v_base, __ATOMIC_RELAXED);
	__atomic_store_n(&p->slice.cpu_base, s.cpu_base, __ATOMIC_RELAXED);
	__atomic_store_n(&p->slice.charged_base, s.charged_base, __ATOMIC_RELAXED);
	__atomic_store_n(&p->slice.own_base, s.own_base, __ATOMIC_RELAXED);
	__atomic_store_n(&p->seq, seq + 2, __ATOMIC_RELEASE);
}

/* The coordinator, each time it runs while the controller may be mid-slice
 * (and with each new slice): estimates made before are stale. */
static inline void tcs_page_bump_gen(struct tcs_clock_page *p)
{
	__atomic_store_n(&p->gen, __atomic_load_n(&p->gen, __ATOMIC_RELAXED) + 1, __ATOMIC_RELEASE);
}

/* The controller's own CPU in slice s when its process CPU clock reads
 * cpu_now: not the hooks' (exit_cpu) nor the runtime's clock reads (own_cpu). */
static inline int64_t tcs_page_slice_cpu(const struct tcs_clock_page *p, struct tcs_slice s, int64_t cpu_now)
{
	int64_t exit_cpu = __atomic_load_n(&p->exit_cpu, __ATOMIC_RELAXED);
	int64_t own = __atomic_load_n(&p->own_cpu, __ATOMIC_RELAXED);
	return tcs_less_own(tcs_slice_cpu(s.cpu_base, exit_cpu, cpu_now), s.own_base, own);
}

/* Lockstep: virtual time is the slice's start, or later by what spinning
 * reached in it (spin_v; from an earlier slice, it is behind v_base). */
static inline int64_t tcs_page_lockstep_v(const struct tcs_clock_page *p, struct tcs_slice s)
{
	int64_t spun = __atomic_load_n(&p->spin_v, __ATOMIC_RELAXED);
	return spun > s.v_base ? spun : s.v_base;
}

/* Virtual time of a controller whose process CPU clock reads cpu_now. */
static inline int64_t tcs_page_vnow(const struct tcs_clock_page *p, struct tcs_slice s, int64_t cpu_now)
{
	if (p->mode == TCS_MODE_LOCKSTEP)
		return tcs_page_lockstep_v(p, s);
	return tcs_ns_add(s.v_base, tcs_scale_cpu(tcs_page_slice_cpu(p, s, cpu_now), p->cpu_scale));
}

/* Virtual CPU time charged to the controller when its CPU clock reads cpu_now. */
static inline int64_t tcs_page_charged(const struct tcs_clock_page *p, struct tcs_slice s, int64_t cpu_now)
{
	return tcs_ns_add(s.charged_base, tcs_scale_cpu(tcs_page_slice_cpu(p, s, cpu_now), p->cpu_scale));
}

#ifdef __cplusplus
}
#endif
#endif
