/* Internal interface of libtcs_preload: the runtime state every hook reads,
 * and the two services hooks are built from (reading virtual time, waiting
 * in virtual time).
 *
 * Rules for everything in this library (it runs inside someone else's
 * program, often in the middle of their signal handler):
 *   - no malloc, no stdio, no locks, no lazy symbol lookup inside a hook;
 *   - talk to the kernel with tcs_sys*() (raw_syscall.h), never via errno;
 *   - internals return -errno; only the exported hook sets errno;
 *   - only hooks are exported (TCS_EXPORT); tests/unit/exports.txt lists them. */
#ifndef TCS_PRELOAD_H
#define TCS_PRELOAD_H

#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <sys/time.h>
#include <time.h>

struct termios;

#include "tcs/clock_page.h"
#include "tcs/device_table.h"
#include "tcs/msg_io.h"
#include "tcs/protocol.h"

#define TCS_EXPORT __attribute__((visibility("default")))
#define TCS_HIDDEN __attribute__((visibility("hidden")))

#include "real.h"

enum tcs_state {
	TCS_OFF = 0,      /* not initialised yet, or not under tcs-run: real time */
	TCS_ON = 1,       /* this process is a controller in virtual time */
	TCS_DETACHED = 2, /* a descendant the coordinator does not schedule */
};

struct tcs_runtime {
	int state;
	long pid; /* the controller's pid */
	int channel_fd;
	int page_fd;
	struct tcs_clock_page *page;
	const struct tcs_device_table *devices; /* beside the page, constant */
	uint32_t next_seq;
};

extern struct tcs_runtime tcs_rt TCS_HIDDEN;

/* Non-zero while this thread is inside a blocking hook: a nested blocking
 * call (from a signal handler) passes straight through. */
extern __thread int tcs_in_wait TCS_HIDDEN __attribute__((tls_model("initial-exec")));

static inline int tcs_active(void)
{
	return __atomic_load_n(&tcs_rt.state, __ATOMIC_RELAXED) == TCS_ON;
}

/* A spin lock for the runtime's small tables (held for a few loads and
 * stores; threads of a controller share one core, so it is rarely seen). */
static inline void tcs_spin_lock(int *lock)
{
	while (__atomic_exchange_n(lock, 1, __ATOMIC_ACQUIRE))
		tcs_cpu_relax();
}

static inline void tcs_spin_unlock(int *lock)
{
	__atomic_store_n(lock, 0, __ATOMIC_RELEASE);
}

/* The process's real CPU time in ns (all threads). */
int64_t tcs_process_cpu(void) TCS_HIDDEN;
/* A clock read straight from the kernel, in ns; -errno on failure. */
int64_t tcs_kernel_clock(clockid_t id) TCS_HIDDEN;
/* The latest virtual time this process has been told (see tcs_vnow). */
extern int64_t tcs_v_seen TCS_HIDDEN;
/* v, or the latest virtual time already told if that is later. Threads
 * share one core, so a plain load and store (no locked instruction) keep
 * it. */
static inline int64_t tcs_v_not_before(int64_t v)
{
	int64_t seen = __atomic_load_n(&tcs_v_seen, __ATOMIC_RELAXED);
	if (v < seen)
		return seen;
	__atomic_store_n(&tcs_v_seen, v, __ATOMIC_RELAXED);
	return v;
}

/* The process's CPU time, estimated without a system call where the clock
 * page allows it (cpu_estimate.c): inline, as clock reads are hot. */
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
/* A child process (children.c): registers with the coordinator through
 * parent_channel and takes its own channel and clock page; 0, or -1 when
 * refused (it then runs in real time). */
int tcs_become_child(int parent_channel, int64_t fork_v, int v_known) TCS_HIDDEN;
void tcs_children_init(void) TCS_HIDDEN;
/* Says once per process that this descendant runs in real time. */
void tcs_tell_detached(struct tcs_clock_page *page) TCS_HIDDEN;
/* Forgets every signal timer (a new child has none). */
void tcs_timers_forget_all(void) TCS_HIDDEN;

/* The thread a timer's signal signo goes to (hooks_timer.c); 0: the process. */
int tcs_timer_signal_target(int signo) TCS_HIDDEN;

/* The process CPU time up to which a request charges it (runtime.c). */
int64_t tcs_charge_point(void) TCS_HIDDEN;
/* In a new child: the CPU readings it inherited are its parent's. */
void tcs_cpu_forget(void) TCS_HIDDEN;
/* The virtual CPU time charged to the controller so far. */
int64_t tcs_charged_now(void) TCS_HIDDEN;

/* Virtual origin of a clock usable for sleeping, or -EINVAL when id is not
 * such a clock (CPU-time and unknown clocks). */
int64_t tcs_sleep_clock_origin(clockid_t id) TCS_HIDDEN;

enum tcs_wait_result {
	TCS_WAIT_DEADLINE = 0, /* the deadline was reached */
	TCS_WAIT_FD = 1,       /* one of the real fds became ready first */
	TCS_WAIT_RECHECK = 2,  /* a step passed; re-check real fds and wait again */
};

/* When a wait is to end, and when it began and ended (virtual ns). */
struct tcs_wait_time {
	int64_t deadline; /* in: absolute, or the timeout if relative; out: absolute */
	int relative;     /* in: deadline is a timeout from the start of the wait */
	int64_t start;    /* out: when the wait began */
	int64_t end;      /* out: when it ended */
	uint32_t seq;     /* in: a sequence number reserved for it (parking.c), or 0 */
};

/* Waits until the virtual deadline (TCS_NEVER: forever). With fds, the wait
 * also ends when one of fds[1..nfds-1] becomes ready; fds[0] is reserved for
 * the channel and mask (may be NULL) is the signal mask during the wait.
 * Returns a tcs_wait_result or -EINTR when a signal handler ran. A deadline
 * already past returns at once without a round trip. The start of the wait
 * is read once, for both the deadline and the BLOCK: one CPU-clock read. */
int tcs_wait(struct tcs_wait_time *t, unsigned kind, unsigned flags, struct pollfd *fds, unsigned nfds,
	     const sigset_t *mask) TCS_HIDDEN;

/* Sends m (its seq is assigned here) and waits for the WAKE answering it,
 * in ppoll over the channel and fds[1..nfds-1] (fds may be NULL) with the
 * signal mask `mask`. A real fd becoming ready or a signal handler running
 * first sends EARLY (and the WAKE still comes). Returns the EARLY reason
 * sent, or 0; the WAKE in *reply; an fd passed with it in *fd_out (or
 * closed when fd_out is NULL). */
unsigned tcs_roundtrip(struct tcs_msg *m, struct pollfd *fds, unsigned nfds, const sigset_t *mask,
		       struct tcs_msg *reply, int *fd_out) TCS_HIDDEN;

/* Enter/leave a blocking hook. tcs_wait_enter() returns 0 when the caller
 * must pass through to the real call (not a controller, a nested call from
 * a signal handler, or no channel for this thread). */
int tcs_wait_enter(void) TCS_HIDDEN;
void tcs_wait_leave(void) TCS_HIDDEN;

/* Writes "tcs: <msg>\n" to stderr the first time it is called with *once == 0. */
void tcs_report_once(int *once, const char *msg) TCS_HIDDEN;

/* Signals to other processes (hooks_signal.c): syscall() by number, and
 * what handlers inside a wait left to tell the coordinator (how many, then
 * told as the wait is left). */
long tcs_signal_syscall(long nr, const long a[6]) TCS_HIDDEN;
extern __thread volatile int tcs_npending_kills TCS_HIDDEN __attribute__((tls_model("initial-exec")));
void tcs_flush_kills(void) TCS_HIDDEN;

/* Exported entry points that no public header declares. */
struct tcs_timeb;
TCS_EXPORT int __nanosleep(const struct timespec *req, struct timespec *rem);
TCS_EXPORT int ftime(struct tcs_timeb *tb);
TCS_EXPORT int __poll_chk(struct pollfd *fds, nfds_t n, int timeout_ms, size_t fdslen);
TCS_EXPORT int __ppoll_chk(struct pollfd *fds, nfds_t n, const struct timespec *ts, const sigset_t *mask,
			   size_t fdslen);
TCS_EXPORT int __open_2(const char *path, int flags);
TCS_EXPORT int __open64_2(const char *path, int flags);
TCS_EXPORT int __openat_2(int dirfd, const char *path, int flags);
TCS_EXPORT int __openat64_2(int dirfd, const char *path, int flags);
TCS_EXPORT long __read_chk(int fd, void *buf, size_t n, size_t buflen);
TCS_EXPORT int pidfd_send_signal(int pidfd, int sig, siginfo_t *info, unsigned flags);

/* Returns -1 with errno = -r when r < 0, else r. The one place hooks turn
 * internal -errno results into the C convention. */
static inline int tcs_errno_result(long r)
{
	if (r < 0) {
		errno = (int)-r;
		return -1;
	}
	return (int)r;
}

/* Threads (threads.c): this thread's channel (made at its first wait), or
 * -errno; the channels of threads other than the main one. */
int tcs_my_channel(void) TCS_HIDDEN;
int tcs_is_thread_channel(int fd) TCS_HIDDEN;
int tcs_thread_channels(int *out, int max) TCS_HIDDEN;
void tcs_threads_init(void) TCS_HIDDEN;
/* In a forked child: the other threads' channels are not its own. */
void tcs_threads_after_fork(void) TCS_HIDDEN;

/* The fds the runtime owns: a program may not close or replace them. */
static inline int tcs_is_runtime_fd(int fd)
{
	return fd >= 0 && (fd == tcs_rt.channel_fd || fd == tcs_rt.page_fd || tcs_is_thread_channel(fd));
}

/* The controller's virtual time now: inline, as clock reads are hot. */
void tcs_catch_up(void);

static inline __attribute__((always_inline)) int64_t tcs_vnow(void)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	if (__builtin_expect(__atomic_load_n(&p->flags, __ATOMIC_RELAXED) & TCS_PAGE_ASLEEP, 0))
		tcs_catch_up();
	/* Lockstep needs no CPU reading: the cheapest path of all. */
	if (p->mode == TCS_MODE_LOCKSTEP)
		return tcs_page_read_slice(p).v_base;
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
