/* The wire protocol between libtcs_preload (in each controller) and the
 * coordinator: fixed-size messages on a private SOCK_SEQPACKET channel, one
 * per controller. This is the only definition; both sides include it.
 *
 * A controller that is about to wait sends BLOCK (the virtual deadline and
 * where it stands) and waits for the WAKE with the same sequence number.
 * If it must stop waiting early (a real fd became ready, a signal handler
 * ran), it sends EARLY and still waits for that WAKE: exactly one WAKE
 * answers every BLOCK, so the two sides can never disagree about which wait
 * is current. Everything a controller sends is untrusted: the coordinator
 * passes each message through tcs_msg_check() before looking at it. */
#ifndef TCS_PROTOCOL_H
#define TCS_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TCS_PROTO_MAGIC 0x31736374u /* "tcs1" */
#define TCS_PROTO_VERSION 10u

/* Environment through which tcs-run hands the channel to the preload. */
#define TCS_ENV_CHANNEL_FD "TCS_CHANNEL_FD"
#define TCS_ENV_PAGE_FD "TCS_PAGE_FD"
#define TCS_ENV_CONTROLLER_PID "TCS_CONTROLLER_PID"
/* Where the preload moves its own descriptors, out of the program's way. */
#define TCS_RUNTIME_FD_FLOOR 900
/* The SCHED_FIFO priority tcs gives controllers where it may (the
 * coordinator's is one above): the preload recognises it. */
#define TCS_CONTROLLER_FIFO_PRIO 2
/* Virtual devices a scenario may declare (see tcs_device_table). */
#define TCS_MAX_DEVICES 64

enum tcs_msg_type {
	TCS_MSG_HELLO = 1, /* controller → coordinator: preload attached (arg = pid, v = this image's nonce) */
	TCS_MSG_BLOCK = 2, /* controller → coordinator: wait until deadline */
	TCS_MSG_EARLY = 3, /* controller → coordinator: end wait seq now (kind = reason) */
	TCS_MSG_WAKE = 4,  /* coordinator → controller: request seq is done (v = its time, arg = result,
			    * deadline = the time the request was charged at) */
	TCS_MSG_DEV_OPEN = 5, /* controller → coordinator: open device arg (flags: TCS_DEV_*) */
	TCS_MSG_DEV_SYNC = 6, /* controller → coordinator: bring device handle arg up to v (kind: TCS_SYNC_*) */
	TCS_MSG_TIMER = 7,    /* controller → coordinator: (re)arm signal timer flags (see below) */
	TCS_MSG_CHILD = 8,    /* a new child → its parent's coordinator: register me (see below) */
	TCS_MSG_THREAD = 9,   /* controller → coordinator: thread arg's own channel (SCM_RIGHTS) */
	TCS_MSG_KILL = 10,    /* controller → coordinator: it signalled process(es) arg (see below) */
	TCS_MSG_DOORBELL = 11, /* controller → coordinator: a request waits in its mailbox (tcs/mailbox.h) */
};

/* Threads. The main thread waits on the controller's channel; every other
 * thread, at its first wait, makes a channel of its own and hands one end
 * over with THREAD (arg = its tid; no answer). Its requests and their WAKEs
 * go on that channel, so each thread has at most one wait outstanding, and
 * the coordinator lets virtual time pass only when no thread can run.
 * Another thread may send EARLY on a waiting thread's channel (it signalled
 * the condition variable, semaphore or futex that thread waits on); an
 * EARLY that arrives before its BLOCK ends that wait as soon as it begins. */

/* A child process (fork, vfork, posix_spawn, system) registers before it
 * runs on: it sends CHILD on its parent's channel with arg = its pid, v =
 * its virtual time at the fork (flags TCS_CHILD_V_KNOWN; else its parent's
 * time now counts) and one end of a new channel (SCM_RIGHTS); then waits on
 * that channel for a WAKE carrying its own clock page (SCM_RIGHTS, arg = 0;
 * arg < 0 and no fd: refused, it runs in real time). From then on it is a
 * controller of its own, with its own virtual CPU. */
enum tcs_child_flags {
	TCS_CHILD_V_KNOWN = 1u << 0,
	/* From the parent, right after fork (no fd): answer once child arg has
	 * registered (or died), so that no time passes before it is counted. */
	TCS_CHILD_PARENT = 1u << 1,
};

/* A signal timer (alarm, setitimer, timer_create): TIMER arms slot `flags`
 * (< TCS_MAX_TIMERS) to send signal `kind` to thread `v` (0: the process)
 * at virtual time `deadline` (TCS_NEVER: disarmed), then every `arg` ns (0:
 * once). The coordinator sends the signal when the controller's virtual time
 * reaches it, stopping a computing controller there. Answered by a WAKE. */
#define TCS_MAX_TIMERS 64

/* A controller sent a signal (kill, killpg, sigqueue, tgkill) to arg, in
 * kill()'s convention: > 0 a process, 0 its own group, < -1 group -arg, -1
 * every process it may signal; v = its virtual time then. A controller the
 * signal reaches gets the core before virtual time passes v, so that it
 * dies or runs its handler then (stepping the world, the coordinator would
 * otherwise keep the core). Answered by a WAKE. */

/* Answering DEV_OPEN, the WAKE carries the device's fd (SCM_RIGHTS) and
 * arg = its handle, or arg = -errno and no fd. Answering DEV_SYNC, arg = 0
 * or -errno (-EAGAIN: nothing due and TCS_DEV_NONBLOCK; -EINVAL: a malformed
 * actuator record). Every request gets exactly one WAKE, as BLOCK does. */
enum tcs_dev_flags {
	TCS_DEV_READ = 1u << 0,     /* opened for reading */
	TCS_DEV_WRITE = 1u << 1,    /* opened for writing */
	TCS_DEV_NONBLOCK = 1u << 2, /* O_NONBLOCK: do not wait for a record */
	TCS_DEV_DEADLINE = 1u << 3, /* SYNC_READ of a wire: wait for data until deadline at most */
	TCS_DEV_FLAGS_ALL = TCS_DEV_READ | TCS_DEV_WRITE | TCS_DEV_NONBLOCK | TCS_DEV_DEADLINE,
};

enum tcs_sync_kind {
	TCS_SYNC_READ = 1,  /* about to read: put what is due into the fd (or wait for it) */
	TCS_SYNC_WRITE = 2, /* just wrote: take the records from the fd, stamped v */
	TCS_SYNC_POLL = 3,  /* about to check readiness: put what is due into the fd */
	TCS_SYNC_DRAIN = 4, /* a wire (tcdrain): wait until what was written has left on the wire */
};

enum tcs_block_kind {
	TCS_BLOCK_SLEEP = 1, /* nanosleep and friends */
	TCS_BLOCK_POLL = 2,  /* select/poll/epoll: real fds may end it early */
	TCS_BLOCK_SYNC = 3,  /* a thread waits for another (condition variable, semaphore, mutex, futex) */
	/* Lockstep: a spin (clock reads, empty reads) reached the clock page's
	 * spin_limit; it goes on from deadline once the world, timers and other
	 * threads are there (libtcs_preload/spin.c). Not the program's wait. */
	TCS_BLOCK_SPIN = 4,
};

enum tcs_block_flags {
	TCS_BLOCK_ABSOLUTE = 1u << 0, /* the program asked for an absolute deadline */
	TCS_BLOCK_RECHECK = 1u << 1,  /* wake at every step so real fds get re-checked */
	TCS_BLOCK_DEVICES = 1u << 2,  /* also wake when a record is due on an open sensor */
	TCS_BLOCK_CHILD = 1u << 3,    /* also wake when a child of the controller ends */
	/* The wait lets signals in by a mask of its own (sigsuspend, ppoll,
	 * pselect, epoll_pwait) and found none pending; arg = the clock page's
	 * signals_raised before it looked. If the coordinator has raised one
	 * since (the look and the BLOCK straddled a preemption), the kernel
	 * would have ended the wait at once: it is answered RECHECK at once. */
	TCS_BLOCK_SIGMASK = 1u << 4,
	/* Sent though already due, to be answered at the coordinator's time
	 * for it: a controller the coordinator stepped aside (asleep outside
	 * the hooks) asks before it reads its clock. */
	TCS_BLOCK_ASK = 1u << 5,
	TCS_BLOCK_FLAGS_ALL = TCS_BLOCK_ABSOLUTE | TCS_BLOCK_RECHECK | TCS_BLOCK_DEVICES | TCS_BLOCK_CHILD |
			      TCS_BLOCK_SIGMASK | TCS_BLOCK_ASK,
};

enum tcs_early_reason {
	TCS_EARLY_FD = 1,     /* a real file descriptor became ready */
	TCS_EARLY_SIGNAL = 2, /* a signal handler ran */
};

enum tcs_wake_reason {
	TCS_WAKE_DEADLINE = 1, /* the deadline was reached */
	TCS_WAKE_EARLY = 2,    /* answered an EARLY */
	TCS_WAKE_RECHECK = 3,  /* a step passed: re-check real fds and block again */
	TCS_WAKE_SIGNAL = 4,   /* timer signals are due (arg: bit n-1 for signal n): raise them */
};

/* WAKE flags. */
enum tcs_wake_flags {
	/* The controller's slice starts with this WAKE (not another thread's
	 * wait ending while the controller runs): what the hook spends from
	 * here on is not charged (clock page: exit_cpu). */
	TCS_WAKE_STARTS_SLICE = 1u << 0,
};

struct tcs_msg {
	uint32_t magic;
	uint16_t version;
	uint16_t type;   /* enum tcs_msg_type */
	uint32_t seq;    /* BLOCK, EARLY, WAKE: which wait */
	uint16_t kind;   /* BLOCK: tcs_block_kind; EARLY: tcs_early_reason; WAKE: tcs_wake_reason */
	uint16_t flags;  /* BLOCK: tcs_block_flags */
	int64_t deadline; /* BLOCK: virtual ns, or TCS_NEVER */
	int64_t v;        /* BLOCK: virtual ns when the wait began; WAKE: when it ended */
	int64_t cpu;      /* BLOCK: process CPU ns when the wait began; EARLY from
			     another thread: when it ended the wait */
	int64_t arg;      /* HELLO: pid */
	int64_t slack;    /* BLOCK: how long after deadline the wait ends when nothing
			     ends it sooner: the waiting thread's timer slack */
};

#if defined(__cplusplus)
static_assert(sizeof(struct tcs_msg) == 56, "wire layout changed: bump TCS_PROTO_VERSION");
static_assert(offsetof(struct tcs_msg, deadline) == 16, "wire layout changed");
#else
_Static_assert(sizeof(struct tcs_msg) == 56, "wire layout changed: bump TCS_PROTO_VERSION");
_Static_assert(offsetof(struct tcs_msg, deadline) == 16, "wire layout changed");
#endif

static inline struct tcs_msg tcs_msg_make(uint16_t type, uint32_t seq)
{
	struct tcs_msg m;
	__builtin_memset(&m, 0, sizeof m);
	m.magic = TCS_PROTO_MAGIC;
	m.version = TCS_PROTO_VERSION;
	m.type = type;
	m.seq = seq;
	return m;
}

/* Validates len bytes received from a controller. Returns NULL and fills
 * *out when they are a well-formed message a controller may send; otherwise
 * a short reason, suitable for "controller N: bad message: <reason>". */
static inline const char *tcs_msg_check(const void *buf, long len, struct tcs_msg *out)
{
	if (len < 0)
		return "receive failed";
	if ((size_t)len != sizeof(struct tcs_msg))
		return "wrong size";
	__builtin_memcpy(out, buf, sizeof *out);
	if (out->magic != TCS_PROTO_MAGIC)
		return "bad magic";
	if (out->version != TCS_PROTO_VERSION)
		return "protocol version mismatch (preload and coordinator from different builds)";
	switch (out->type) {
	case TCS_MSG_HELLO:
		if (out->arg <= 0 || out->arg > INT32_MAX)
			return "HELLO with an invalid pid";
		return NULL;
	case TCS_MSG_BLOCK:
		if (out->kind < TCS_BLOCK_SLEEP || out->kind > TCS_BLOCK_SPIN)
			return "BLOCK of unknown kind";
		if (out->flags & ~TCS_BLOCK_FLAGS_ALL)
			return "BLOCK with unknown flags";
		if (out->deadline < 0 || out->v < 0 || out->cpu < 0 || out->slack < 0)
			return "BLOCK with a negative time";
		return NULL;
	case TCS_MSG_EARLY:
		if (out->kind != TCS_EARLY_FD && out->kind != TCS_EARLY_SIGNAL)
			return "EARLY with unknown reason";
		return NULL;
	case TCS_MSG_DEV_OPEN:
		if (out->arg < 0 || out->arg >= TCS_MAX_DEVICES)
			return "DEV_OPEN of a device that does not exist";
		if (out->flags & ~TCS_DEV_FLAGS_ALL || !(out->flags & (TCS_DEV_READ | TCS_DEV_WRITE)))
			return "DEV_OPEN with bad flags";
		return NULL;
	case TCS_MSG_DEV_SYNC:
		if (out->kind < TCS_SYNC_READ || out->kind > TCS_SYNC_DRAIN)
			return "DEV_SYNC of unknown kind";
		if (out->flags & ~TCS_DEV_FLAGS_ALL)
			return "DEV_SYNC with bad flags";
		if (out->arg < 0 || out->arg > INT32_MAX || out->v < 0 || out->cpu < 0 ||
		    ((out->flags & TCS_DEV_DEADLINE) && out->deadline < 0))
			return "DEV_SYNC with a bad handle or time";
		return NULL;
	case TCS_MSG_TIMER:
		if (out->flags >= TCS_MAX_TIMERS || out->kind < 1 || out->kind > 64)
			return "TIMER with a bad slot or signal";
		if (out->deadline < 0 || out->arg < 0 || out->v < 0 || out->v > INT32_MAX || out->cpu < 0)
			return "TIMER with a negative time or a bad thread";
		return NULL;
	case TCS_MSG_CHILD:
		if (out->arg <= 0 || out->arg > INT32_MAX || out->v < 0 || out->cpu < 0 ||
		    out->flags & ~(TCS_CHILD_V_KNOWN | TCS_CHILD_PARENT))
			return "CHILD with an invalid pid, time or flags";
		return NULL;
	case TCS_MSG_THREAD:
		if (out->arg <= 0 || out->arg > INT32_MAX)
			return "THREAD with an invalid tid";
		return NULL;
	case TCS_MSG_KILL:
		if (out->arg < -(int64_t)INT32_MAX || out->arg > INT32_MAX || out->v < 0 || out->cpu < 0)
			return "KILL with an invalid pid or time";
		return NULL;
	case TCS_MSG_DOORBELL:
		return NULL;
	case TCS_MSG_WAKE:
		return "WAKE is sent by the coordinator, not to it";
	default:
		return "unknown message type";
	}
}

#ifdef __cplusplus
}
#endif
#endif
