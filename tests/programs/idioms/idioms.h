/* The idiom corpus's program (main.c says what it does): what its files
 * share. Each call of the corpus is a function c_NAME(struct ctx *) in one
 * of calls_*.c, listed in table.c; the contexts it is made from are in
 * contexts.c; common.c keeps the run's findings. */
#ifndef TCS_IDIOMS_H
#define TCS_IDIOMS_H

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <semaphore.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/ioctl.h>
#include <sys/pidfd.h>
#include <sys/prctl.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/timerfd.h>
#include <sys/times.h>
#include <sys/uio.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <termios.h>
#include <threads.h>
#include <time.h>
#include <unistd.h>

#define ROUNDS 20
#define MS 1000000LL
#define SEC 1000000000LL
/* Short waits (200 us to 2 ms, as the corpus asks): a wait with a timeout
 * sleeps SLEEP_NS; poll and epoll, which count in ms, POLL_MS. */
#define SLEEP_NS 500000LL
#define POLL_MS 1
/* A wake-up signal for pause and sigsuspend comes this long after arming. */
#define WAKE_NS 300000LL
/* The SIGALRM driver's period, and the nested SIGUSR1's. */
#define PERIOD_NS (2 * MS)
#define NEST_NS 1500000LL
/* A SIGALRM handler of the nested context loops over its INTERRUPTED call
 * until a SIGUSR1 has come, or this long: less than the period, or the
 * next SIGALRM would be pending as it returns, and main would starve. */
#define NEST_CAP_NS (PERIOD_NS * 9 / 10)
/* A run that has not made its ROUNDS calls after this long gives up (and
 * fails): a bound on virtual time far above the ~50 ms a run takes. */
#define GIVE_UP_NS (5 * SEC)
/* The timers the probes arm: long enough never to expire in a run. */
#define PROBE_NS (10 * SEC)
#define ARMED_NS (100 * SEC)
/* time() may read the coarse clock, which lags by up to one tick. */
#define COARSE_LAG_NS (10 * MS)

enum { ROLE_CALL, ROLE_FLOW };
/* Who makes a call: each has its own descriptors and timers, so a handler
 * never checks what the flow it interrupted is changing. */
enum { WHO_MAIN, WHO_HANDLER, WHO_NESTED, WHOS };

/* What a call needs set up before it runs (struct flow). */
enum {
	NEED_PIPE = 1 << 0,
	NEED_EPOLL = 1 << 1,
	NEED_IDLE = 1 << 2,
	NEED_ARMED = 1 << 3,
	NEED_WAKE = 1 << 4,
	NEED_TFD_ARMED = 1 << 5,
	NEED_TFD_TICK = 1 << 6,
	NEED_SEM = 1 << 7,
	NEED_DEV = 1 << 8,
};

struct flow {
	int ready;
	int pipe_r, pipe_w;  /* an empty pipe: what multiplexers wait on */
	int epfd;            /* epoll set holding pipe_r */
	timer_t idle;        /* a signal timer (SIGRTMAX), disarmed */
	timer_t armed;       /* a SIGEV_NONE timer armed ARMED_NS */
	long long armed_at;  /* CLOCK_MONOTONIC just before arming `armed` */
	timer_t wake;        /* signals wake(who) to the flow's thread */
	int tfd_armed;       /* a timerfd armed ARMED_NS */
	long long tfd_armed_at;
	int tfd_tick; /* a timerfd ticking every SLEEP_NS */
	sem_t sem;    /* stays 0 */
	int state_fd, torque_fd;
	char line[512]; /* what state_fd has given beyond its last whole line */
	size_t line_len;
	unsigned round; /* calls made: alternates variants of a call */
};

/* What a run found, kept with atomics only, as handlers update it. A fork
 * child sends its own back whole through a pipe. */
struct stats {
	long long calls[2], sleeps[2], sleep_min[2], sleep_max[2];
	long long over_max[2]; /* the most a wait lasted beyond what it asked */
	long long eintr, absent, failures;
	int first_set, first_errno, first_value; /* first_value: not an errno */
	int first_role;
	const char *first_call, *first_what;      /* literals: the same in a child */
	long long slack;                          /* PR_GET_TIMERSLACK, -1: not read */
};

/* How ITIMER_REAL may be checked: exclusively this flow's (strict), the
 * SIGALRM driver's (calls re-arm it as the driver does), or shared by
 * the interrupted flow and the handler (only what holds either way). */
enum { IT_STRICT, IT_DRIVER, IT_SHARED };

struct ctx {
	struct flow *f;
	int who, role;
	const char *name;
};

#endif
