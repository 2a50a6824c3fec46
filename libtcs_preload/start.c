/* Start-up: the constructor runs one ordered list of steps, each of which
 * may end start-up early (the process then runs in real time). Until the
 * last step this process is not a controller (TCS_OFF) and every hook
 * passes its call through.
 *
 * The constructor runs single-threaded, before main(), and may use libc
 * freely. It stands above every file whose step it runs (children,
 * journal, channels, the CPU clock), so that the state they all share
 * (runtime.c) stands below them all and calls none of them. */
#include <stdlib.h>
#include <sys/mman.h>

#include "child.h"
#include "cpu_estimate.h"
#include "journal_write.h"
#include "raw_syscall.h"
#include "real.h"
#include "replay.h"
#include "report.h"
#include "roundtrip.h"
#include "thread_channels.h"
#include "vclock.h"
#include "wait.h"

static int tcs_env_int(const char *name, long *out)
{
	const char *s = getenv(name);
	char *end;
	if (!s || !*s)
		return -ENOENT;
	*out = strtol(s, &end, 10);
	return *end == '\0' ? 0 : -EINVAL;
}

/* ---- the steps, in the order they run: 0 to go on, 1 to stop ---------------- */

static int tcs_start_real_functions(void)
{
	tcs_real_resolve();
	return 0;
}

/* The clock's ways up into the waits (vclock.h), before any clock is read. */
static int tcs_start_clock_ways_up(void)
{
	tcs_vclock_up.catch_up = tcs_catch_up;
	tcs_vclock_up.journal_request = tcs_replay_request;
	return 0;
}

static int tcs_start_thread_channels(void)
{
	tcs_thread_channels_init();
	return 0;
}

/* The test suite's slow-clock setup (cpu_estimate.c). */
static int tcs_start_slow_clock(void)
{
	long delay;
	if (tcs_env_int("TCS_CPU_CLOCK_DELAY_NS", &delay) == 0 && delay > 0)
		tcs_cpu_clock_delay_set(delay);
	return 0;
}

/* The channel and clock page tcs-run handed over; without them this
 * program was not started by tcs-run. */
static int tcs_start_environment(void)
{
	long channel, page, controller;
	if (tcs_env_int(TCS_ENV_CHANNEL_FD, &channel) || tcs_env_int(TCS_ENV_PAGE_FD, &page) ||
	    tcs_env_int(TCS_ENV_CONTROLLER_PID, &controller)) {
		tcs_say("libtcs_preload.so loaded outside tcs-run; this program runs in real time", NULL, NULL);
		return 1;
	}
	(void)controller; /* the page says whose it is */
	tcs_rt.pid = tcs_sys0(SYS_getpid);
	tcs_rt.channel_fd = (int)channel;
	tcs_rt.page_fd = (int)page;
	return 0;
}

static int tcs_start_clock_page(void)
{
	void *m = mmap(NULL, TCS_SHARED_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, tcs_rt.page_fd, 0);
	if (m == MAP_FAILED) {
		/* No page of ours: a descendant that closed it, or a stray. */
		tcs_detach_descendant(-1);
		return 1;
	}
	tcs_rt.page = (struct tcs_clock_page *)m;
	tcs_rt.devices = tcs_device_table_of(m);
	if (tcs_rt.page->magic != TCS_PAGE_MAGIC || tcs_rt.page->version != TCS_PAGE_VERSION) {
		tcs_say("libtcs_preload.so does not match the coordinator (mixed installations?)",
			"; refusing to run in real time", NULL);
		tcs_sys1(SYS_exit_group, 2);
	}
	return 0;
}

/* A child started by vfork or posix_spawn, its new program just loaded,
 * the page its parent's: it registers now. */
static int tcs_start_as_child(void)
{
	if (tcs_rt.page->owner_pid == tcs_rt.pid)
		return 0;
	if (tcs_become_child(tcs_rt.channel_fd, 0, 0) == 0)
		return 0;
	struct tcs_clock_page *parents = tcs_rt.page;
	tcs_rt.page = NULL;
	tcs_rt.state = TCS_DETACHED;
	tcs_tell_detached(parents);
	tcs_sys2(SYS_munmap, parents, TCS_SHARED_SIZE);
	return 1;
}

/* Children forked from here on register in the fork's child handler. */
static int tcs_start_fork_handlers(void)
{
	tcs_child_init();
	return 0;
}

static int tcs_start_hello(void)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_HELLO, 0);
	m.arg = tcs_sys0(SYS_getpid);
	/* Tells this program image from the one before an exec: a HELLO with
	 * the same value again is a misbehaving program, not a new image. */
	m.v = tcs_kernel_clock(CLOCK_MONOTONIC);
	tcs_send(tcs_rt.channel_fd, &m);
	return 0;
}

static int (*const tcs_start_steps[])(void) = {
	tcs_start_real_functions,  /* before any hook passes a call on */
	tcs_start_clock_ways_up,
	tcs_start_thread_channels, /* the key that closes an ending thread's channel */
	tcs_start_slow_clock,
	tcs_start_environment,     /* stops outside tcs-run */
	tcs_start_clock_page,      /* stops in a descendant with no page */
	tcs_start_as_child,        /* stops when the coordinator refuses it */
	tcs_start_journal,         /* --record, --replay: the page says */
	tcs_start_fork_handlers,
	tcs_start_hello,
};

__attribute__((constructor)) static void tcs_init(void)
{
	int saved_errno = errno;
	size_t i = 0;
	while (i < sizeof tcs_start_steps / sizeof *tcs_start_steps && tcs_start_steps[i]() == 0)
		i++;
	if (i == sizeof tcs_start_steps / sizeof *tcs_start_steps)
		__atomic_store_n(&tcs_rt.state, TCS_ON, __ATOMIC_RELEASE);
	errno = saved_errno;
}
