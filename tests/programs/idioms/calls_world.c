/* The idioms program's calls on the pendulum's devices, signals sent to
 * oneself, semaphores, condition variables and randomness. */
#include "calls_timers.h"
#include "calls_world.h"
#include "common.h"
#include "contexts.h"

/* ---- the pendulum's devices ---- */

static int number(const char **p)
{
	const char *s = *p;
	int digits = 0;
	if (*s == '-' || *s == '+')
		s++;
	for (; *s >= '0' && *s <= '9'; s++)
		digits++;
	if (*s == '.')
		for (s++; *s >= '0' && *s <= '9'; s++)
			digits++;
	if (digits && (*s == 'e' || *s == 'E')) {
		int e = 0;
		if (*++s == '-' || *s == '+')
			s++;
		for (; *s >= '0' && *s <= '9'; s++)
			e++;
		if (!e)
			return 0;
	}
	*p = s;
	return digits > 0;
}

/* A state record: "angle velocity\n". */
static int state_line(const char *s)
{
	if (!number(&s) || *s != ' ')
		return 0;
	while (*s == ' ')
		s++;
	return number(&s) && *s == '\n';
}

/* The device is not there: natively it never is. */
static int device_missing(struct ctx *c, int err)
{
	if (err == ENOENT) {
		sum(&S.absent, 1);
		return 1;
	}
	fail(c, "open", err);
	return 1;
}

static ssize_t read_some(struct ctx *c, int fd, char *buf, size_t len)
{
	ssize_t n;
	while ((n = read(fd, buf, len)) < 0 && errno == EINTR)
		interrupted();
	if (n < 0)
		fail(c, "read", errno);
	return n;
}

static void write_all(struct ctx *c, int fd, const char *s, size_t len)
{
	ssize_t n;
	while ((n = write(fd, s, len)) < 0 && errno == EINTR)
		interrupted();
	if (n < 0)
		fail(c, "write", errno);
	else
		check(c, (size_t)n == len, "short_write");
}

/* open, read a record, close. */
void c_dev_read(struct ctx *c)
{
	int fd = open(STATE, O_RDONLY | O_CLOEXEC);
	if (fd < 0) {
		device_missing(c, errno);
		return;
	}
	char buf[256];
	ssize_t n = read_some(c, fd, buf, sizeof buf - 1);
	if (n > 0) {
		buf[n] = 0;
		check(c, state_line(buf), "record");
	} else if (n == 0) {
		fail(c, "eof", 0);
	}
	if (close(fd) != 0)
		fail(c, "close", errno);
}

/* openat, write a torque command, close. */
void c_dev_write(struct ctx *c)
{
	int fd = openat(AT_FDCWD, TORQUE, O_WRONLY | O_CLOEXEC);
	if (fd < 0) {
		device_missing(c, errno);
		return;
	}
	write_all(c, fd, "0.1\n", 4);
	if (close(fd) != 0)
		fail(c, "close", errno);
}

/* The control loop's way: a record from a state fd kept open (whole lines
 * are checked; a piece of one waits for the rest), a command to a torque
 * fd kept open. */
void c_dev_fd(struct ctx *c)
{
	struct flow *f = c->f;
	if (f->state_fd < 0 || f->torque_fd < 0) {
		sum(&S.absent, 1);
		return;
	}
	int lines = 0;
	while (!lines) {
		if (f->line_len >= sizeof f->line - 1) {
			fail(c, "no_newline", 0);
			f->line_len = 0;
			return;
		}
		ssize_t n = read_some(c, f->state_fd, f->line + f->line_len, sizeof f->line - 1 - f->line_len);
		if (n <= 0) {
			if (n == 0)
				fail(c, "eof", 0);
			return;
		}
		f->line_len += n;
		f->line[f->line_len] = 0;
		char *start = f->line, *nl;
		while ((nl = memchr(start, '\n', f->line + f->line_len - start))) {
			check(c, state_line(start), "record");
			lines++;
			start = nl + 1;
		}
		f->line_len -= start - f->line;
		memmove(f->line, start, f->line_len);
	}
	write_all(c, f->torque_fd, "0\n", 2);
}

/* stdio, as most controllers read their sensors (not async-signal-safe). */
void c_dev_fopen(struct ctx *c)
{
	FILE *in = fopen(STATE, "re");
	if (!in) {
		device_missing(c, errno);
		return;
	}
	char buf[256];
	if (!fgets(buf, sizeof buf, in))
		fail(c, "fgets", errno);
	else
		check(c, state_line(buf), "record");
	if (fclose(in) != 0)
		fail(c, "fclose", errno);
}

/* ---- signals to oneself: handled before the call returns (POSIX, for a
 * signal no other thread has unblocked) ---- */

void sent(struct ctx *c, int seen, int code, const char *what)
{
	check(c, wakes[c->who] != seen, what);
	check(c, wake_code[c->who] == code, "si_code");
	if (code == SI_USER || code == SI_QUEUE)
		check(c, wake_pid[c->who] == getpid(), "si_pid");
}

void c_kill(struct ctx *c)
{
	int seen = wakes[c->who];
	if (kill(getpid(), wake_sig(c->who)) != 0)
		fail(c, "kill", errno);
	sent(c, seen, SI_USER, "not_handled");
}

void c_raise(struct ctx *c)
{
	int seen = wakes[c->who];
	if (raise(wake_sig(c->who)) != 0)
		fail(c, "raise", errno);
	sent(c, seen, SI_TKILL, "not_handled");
}

void c_sigqueue(struct ctx *c)
{
	int seen = wakes[c->who];
	if (sigqueue(getpid(), wake_sig(c->who), (union sigval){ .sival_int = 35 + c->who }) != 0)
		fail(c, "sigqueue", errno);
	sent(c, seen, SI_QUEUE, "not_handled");
	check(c, wake_value[c->who] == 35 + c->who, "si_value");
}

void c_tgkill(struct ctx *c)
{
	int seen = wakes[c->who];
	if (tgkill(getpid(), gettid(), wake_sig(c->who)) != 0)
		fail(c, "tgkill", errno);
	sent(c, seen, SI_TKILL, "not_handled");
}

void c_pidfd_send_signal(struct ctx *c)
{
	int pidfd = pidfd_open(getpid(), 0);
	if (pidfd < 0) {
		fail(c, "pidfd_open", errno);
		return;
	}
	int seen = wakes[c->who];
	if (pidfd_send_signal(pidfd, wake_sig(c->who), NULL, 0) != 0)
		fail(c, "pidfd_send_signal", errno);
	sent(c, seen, SI_USER, "not_handled");
	close(pidfd);
}

/* Waits for a child, restarting after a handler; its status, or -1. */
int reap(struct ctx *c, pid_t pid)
{
	int st;
	pid_t r;
	while ((r = waitpid(pid, &st, 0)) < 0 && errno == EINTR)
		interrupted();
	if (r != pid) {
		fail(c, "waitpid", errno);
		return -1;
	}
	return st;
}

void exited_zero(struct ctx *c, int st)
{
	if (st != -1 && !(WIFEXITED(st) && WEXITSTATUS(st) == 0))
		fail_with(c, WIFSIGNALED(st) ? "child_killed" : "child_failed", 0, WIFSIGNALED(st) ? WTERMSIG(st) : WEXITSTATUS(st));
}

/* A child that waits for signals; SIGTERM ends it. */
void c_kill_child(struct ctx *c)
{
	pid_t pid = fork();
	if (pid < 0) {
		fail(c, "fork", errno);
		return;
	}
	if (pid == 0) {
		sigset_t term;
		sigemptyset(&term);
		sigaddset(&term, SIGTERM);
		sigprocmask(SIG_UNBLOCK, &term, NULL); /* the caller's mask is the child's */
		for (;;)
			pause();
	}
	if (kill(pid, SIGTERM) != 0)
		fail(c, "kill", errno);
	int st = reap(c, pid);
	if (st != -1)
		check(c, WIFSIGNALED(st) && WTERMSIG(st) == SIGTERM, "not_terminated");
}

/* ---- semaphores and condition variables ---- */

/* sem_timedwait on CLOCK_REALTIME, every other time sem_clockwait on
 * CLOCK_MONOTONIC, on a semaphore at 0: times out at its deadline. */
void c_sem_timedwait(struct ctx *c)
{
	int mono = c->f->round % 2;
	clockid_t clk = mono ? CLOCK_MONOTONIC : CLOCK_REALTIME;
	long long t0 = mono_ns(), deadline = clock_read(clk) + SLEEP_NS;
	struct timespec at = ts_of(deadline);
	int r;
	while ((r = mono ? sem_clockwait(&c->f->sem, clk, &at) : sem_timedwait(&c->f->sem, &at)) != 0 && errno == EINTR)
		interrupted();
	if (r == 0 || errno != ETIMEDOUT)
		fail(c, r == 0 ? "acquired" : "sem_timedwait", r == 0 ? 0 : errno);
	check(c, clock_read(clk) >= deadline, "before_deadline");
	waited(c, t0, mono_ns(), SLEEP_NS);
}

void c_sem_post(struct ctx *c)
{
	if (sem_post(&c->f->sem) != 0) {
		fail(c, "sem_post", errno);
		return;
	}
	while (sem_wait(&c->f->sem) != 0) {
		if (errno != EINTR) {
			fail(c, "sem_wait", errno);
			return;
		}
		interrupted();
	}
	int v = -1;
	sem_getvalue(&c->f->sem, &v);
	check(c, v == 0, "value");
}

/* pthread_cond_timedwait (CLOCK_REALTIME), every other time
 * pthread_cond_clockwait (CLOCK_MONOTONIC), with nobody to signal. */
void c_cond_timedwait(struct ctx *c)
{
	pthread_mutex_t m = PTHREAD_MUTEX_INITIALIZER;
	pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
	int mono = c->f->round % 2;
	clockid_t clk = mono ? CLOCK_MONOTONIC : CLOCK_REALTIME;
	long long t0 = mono_ns(), deadline = clock_read(clk) + SLEEP_NS;
	struct timespec at = ts_of(deadline);
	pthread_mutex_lock(&m);
	int e;
	do /* a spurious wake-up (0) waits again */
		e = mono ? pthread_cond_clockwait(&cv, &m, clk, &at) : pthread_cond_timedwait(&cv, &m, &at);
	while (e == 0);
	pthread_mutex_unlock(&m);
	if (e != ETIMEDOUT)
		fail(c, "pthread_cond_timedwait", e);
	check(c, clock_read(clk) >= deadline, "before_deadline");
	waited(c, t0, mono_ns(), SLEEP_NS);
}

/* ---- randomness ---- */

void c_getrandom(struct ctx *c)
{
	unsigned char b[16] = { 0 };
	ssize_t n;
	while ((n = getrandom(b, sizeof b, 0)) < 0 && errno == EINTR)
		interrupted();
	if (n != (ssize_t)sizeof b)
		fail(c, "getrandom", n < 0 ? errno : 0);
}

void c_urandom(struct ctx *c)
{
	int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
	if (fd < 0) {
		fail(c, "open", errno);
		return;
	}
	char b[16];
	check(c, read_some(c, fd, b, sizeof b) == (ssize_t)sizeof b, "short_read");
	if (close(fd) != 0)
		fail(c, "close", errno);
}
