/* The idioms program's table of calls, and what each needs set up first. */
#include "calls_processes.h"
#include "calls_time.h"
#include "calls_timers.h"
#include "calls_world.h"
#include "common.h"
#include "contexts.h"
#include "table.h"

/* ---- the table ---- */

const struct call calls[] = {
	{ "clock_mono", c_clock_mono, F_POSIX | F_INTERRUPTED | F_VFORK, 0 },
	{ "clock_real", c_clock_real, F_POSIX | F_VFORK, 0 },
	{ "clock_process", c_clock_process, F_POSIX, 0 },
	{ "clock_thread", c_clock_thread, F_POSIX | F_INTERRUPTED, 0 },
	{ "gettimeofday", c_gettimeofday, F_INTERRUPTED, 0 },
	{ "time", c_time, F_POSIX, 0 },
	{ "timespec_get", c_timespec_get, 0, 0 },
	{ "clock", c_clock, F_INTERRUPTED, 0 },
	{ "times", c_times, F_POSIX, 0 },
	{ "getrusage", c_getrusage, 0, 0 },
	{ "nanosleep", c_nanosleep, F_INTERRUPTED, 0 },
	{ "clock_nanosleep", c_clock_nanosleep, 0, 0 },
	{ "clock_nanosleep_abs", c_clock_nanosleep_abs, F_INTERRUPTED, 0 },
	{ "usleep", c_usleep, F_INTERRUPTED, 0 },
	{ "sleep", c_sleep, F_POSIX, 0 },
	{ "thrd_sleep", c_thrd_sleep, 0, 0 },
	{ "select", c_select, F_POSIX | F_INTERRUPTED, NEED_PIPE },
	{ "pselect", c_pselect, F_POSIX, NEED_PIPE },
	{ "poll", c_poll, F_POSIX | F_INTERRUPTED, NEED_PIPE },
	{ "ppoll", c_ppoll, 0, NEED_PIPE },
	{ "epoll_wait", c_epoll_wait, F_INTERRUPTED, NEED_PIPE | NEED_EPOLL },
	{ "epoll_pwait", c_epoll_pwait, 0, NEED_PIPE | NEED_EPOLL },
	{ "alarm", c_alarm, F_POSIX, 0 },
	{ "setitimer", c_setitimer, F_INTERRUPTED, 0 },
	{ "getitimer", c_getitimer, F_INTERRUPTED, 0 },
	{ "timer_create", c_timer_create, 0, 0 },
	{ "timer_settime", c_timer_settime, F_POSIX | F_INTERRUPTED, NEED_IDLE },
	{ "timer_gettime", c_timer_gettime, F_POSIX | F_INTERRUPTED, NEED_ARMED },
	{ "timer_getoverrun", c_timer_getoverrun, F_POSIX, NEED_ARMED },
	{ "timerfd", c_timerfd, 0, 0 },
	{ "timerfd_gettime", c_timerfd_gettime, F_INTERRUPTED, NEED_TFD_ARMED },
	{ "timerfd_read", c_timerfd_read, F_INTERRUPTED, NEED_TFD_TICK },
	{ "sigsuspend", c_sigsuspend, F_POSIX | F_INTERRUPTED, NEED_WAKE },
	{ "pause", c_pause, F_POSIX | F_INTERRUPTED, NEED_WAKE },
	{ "dev_read", c_dev_read, F_POSIX, 0 },
	{ "dev_write", c_dev_write, F_POSIX, 0 },
	{ "dev_fd", c_dev_fd, F_POSIX | F_INTERRUPTED, NEED_DEV },
	{ "dev_fopen", c_dev_fopen, 0, 0 },
	{ "kill", c_kill, F_POSIX, 0 },
	{ "raise", c_raise, F_POSIX, 0 },
	{ "sigqueue", c_sigqueue, F_POSIX, 0 },
	{ "tgkill", c_tgkill, 0, 0 },
	{ "pidfd_send_signal", c_pidfd_send_signal, 0, 0 },
	{ "kill_child", c_kill_child, F_POSIX, 0 },
	{ "sem_timedwait", c_sem_timedwait, F_INTERRUPTED, NEED_SEM },
	{ "sem_post", c_sem_post, F_POSIX, NEED_SEM },
	{ "cond_timedwait", c_cond_timedwait, 0, 0 },
	{ "getrandom", c_getrandom, 0, 0 },
	{ "urandom", c_urandom, F_POSIX, 0 },
	{ "fork", c_fork, F_POSIX, 0 },
	{ "exec", c_exec, F_POSIX | F_VFORK, 0 },
	{ "vfork", c_vfork, 0, 0 },
	{ "posix_spawn", c_posix_spawn, 0, 0 },
	{ "system", c_system, 0, 0 },
	{ "socket", c_socket, F_POSIX, 0 },
	{ "tcattr", c_tcattr, F_POSIX, 0 },
	{ "dup", c_dup, F_POSIX, NEED_PIPE },
	{ "pipe_io", c_pipe_io, 0, 0 },
	{ "close_range", c_close_range, 0, NEED_PIPE },
	{ "prctl", c_prctl, 0, 0 },
};
const int ncalls = (int)(sizeof calls / sizeof calls[0]);

int call_id(const char *name)
{
	for (int i = 0; i < ncalls; i++)
		if (strcmp(calls[i].name, name) == 0)
			return i;
	return -1;
}

/* ---- setting a flow up ---- */

/* What the run needs failed (not a call under test): exit 3. */
void die(const char *what)
{
	fprintf(stderr, "idioms: %s: %s\n", what, strerror(errno));
	exit(3);
}

void setup(int who, int id)
{
	struct flow *f = &flows[who];
	int needs = calls[id].needs;
	if (!f->ready) {
		f->ready = 1;
		f->pipe_r = f->pipe_w = f->epfd = f->tfd_armed = f->tfd_tick = f->state_fd = f->torque_fd = -1;
	}
	if ((needs & NEED_PIPE) && f->pipe_r < 0) {
		int p[2];
		if (pipe2(p, O_CLOEXEC) != 0)
			die("pipe");
		f->pipe_r = p[0];
		f->pipe_w = p[1];
	}
	if ((needs & NEED_EPOLL) && f->epfd < 0) {
		struct epoll_event ev = { .events = EPOLLIN };
		if ((f->epfd = epoll_create1(EPOLL_CLOEXEC)) < 0 || epoll_ctl(f->epfd, EPOLL_CTL_ADD, f->pipe_r, &ev) != 0)
			die("epoll");
	}
	/* A signal timer, never expiring: a SIGEV_NONE timer shows, once
	 * disarmed, what was left at the disarming (Linux 6.18) */
	struct sigevent stray = { .sigev_notify = SIGEV_SIGNAL, .sigev_signo = SIGRTMAX };
	if ((needs & NEED_IDLE) && timer_create(CLOCK_MONOTONIC, &stray, &f->idle) != 0)
		die("timer_create");
	struct sigevent none = { .sigev_notify = SIGEV_NONE };
	if (needs & NEED_ARMED) {
		struct itimerspec on = { { 0, 0 }, ts_of(ARMED_NS) };
		f->armed_at = mono_ns();
		if (timer_create(CLOCK_MONOTONIC, &none, &f->armed) != 0 || timer_settime(f->armed, 0, &on, NULL) != 0)
			die("timer_create");
	}
	if (needs & NEED_WAKE) {
		struct sigevent ev = { .sigev_notify = SIGEV_THREAD_ID, .sigev_signo = wake_sig(who) };
		ev._sigev_un._tid = gettid(); /* sigev_notify_thread_id: not in glibc 2.36 */
		if (timer_create(CLOCK_MONOTONIC, &ev, &f->wake) != 0)
			die("timer_create");
	}
	if (needs & NEED_TFD_ARMED) {
		struct itimerspec on = { { 0, 0 }, ts_of(ARMED_NS) };
		f->tfd_armed_at = mono_ns();
		if ((f->tfd_armed = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC)) < 0 ||
		    timerfd_settime(f->tfd_armed, 0, &on, NULL) != 0)
			die("timerfd");
	}
	if (needs & NEED_TFD_TICK) {
		struct itimerspec on = { ts_of(SLEEP_NS), ts_of(SLEEP_NS) };
		if ((f->tfd_tick = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC)) < 0 ||
		    timerfd_settime(f->tfd_tick, 0, &on, NULL) != 0)
			die("timerfd");
	}
	if ((needs & NEED_SEM) && sem_init(&f->sem, 0, 0) != 0)
		die("sem_init");
	if (needs & NEED_DEV) {
		f->state_fd = open(STATE, O_RDONLY | O_CLOEXEC);
		f->torque_fd = open(TORQUE, O_WRONLY | O_CLOEXEC);
		if ((f->state_fd < 0 || f->torque_fd < 0) && errno != ENOENT)
			die("open a device");
	}
}

void do_call(int id, int who, int role)
{
	struct ctx c = { &flows[who], who, role, calls[id].name };
	calls[id].fn(&c);
	flows[who].round++;
	sum(&S.calls[role], 1);
}
