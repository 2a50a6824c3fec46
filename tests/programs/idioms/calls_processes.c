/* The idioms program's calls that make processes, and those on
 * descriptors. */
#include "calls_processes.h"
#include "calls_timers.h"
#include "calls_world.h"
#include "common.h"
#include "contexts.h"

/* ---- processes ---- */

/* The child's clock starts where its parent's was at the fork. */
void c_fork(struct ctx *c)
{
	long long before = mono_ns();
	pid_t pid = fork();
	if (pid < 0) {
		fail(c, "fork", errno);
		return;
	}
	if (pid == 0)
		_exit(mono_ns() >= before ? 0 : 3);
	exited_zero(c, reap(c, pid));
}

void c_exec(struct ctx *c)
{
	pid_t pid = fork();
	if (pid < 0) {
		fail(c, "fork", errno);
		return;
	}
	if (pid == 0) {
		execl("/bin/true", "true", (char *)NULL);
		_exit(127);
	}
	exited_zero(c, reap(c, pid));
}

/* vfork, and a child that only _exits; reaped with wait(). */
void c_vfork(struct ctx *c)
{
	pid_t pid = vfork();
	if (pid < 0) {
		fail(c, "vfork", errno);
		return;
	}
	if (pid == 0)
		_exit(0);
	int st;
	pid_t r;
	while ((r = wait(&st)) < 0 && errno == EINTR)
		interrupted();
	if (r != pid)
		fail(c, "wait", errno);
	else
		exited_zero(c, st);
}

extern char **environ;

void c_posix_spawn(struct ctx *c)
{
	pid_t pid;
	char *argv[] = { "true", NULL };
	int e = posix_spawn(&pid, "/bin/true", NULL, NULL, argv, environ);
	if (e != 0) {
		fail(c, "posix_spawn", e);
		return;
	}
	exited_zero(c, reap(c, pid));
}

void c_system(struct ctx *c)
{
	int st = system("true");
	if (st == -1)
		fail(c, "system", errno);
	else
		exited_zero(c, st);
}

/* ---- descriptors ---- */

/* Writes n's decimal digits at p; returns the end. */
static char *put_int(char *p, long n)
{
	char d[24];
	int k = 0;
	do
		d[k++] = '0' + n % 10;
	while ((n /= 10) > 0);
	while (k)
		*p++ = d[--k];
	return p;
}

/* A datagram socket bound to an abstract name of its own, that sends to
 * itself with sendto, send (connected) and sendmsg, and reads each back
 * with recvfrom, recv and recvmsg; its options and name read back. */
void c_socket(struct ctx *c)
{
	int s = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
	if (s < 0) {
		fail(c, "socket", errno);
		return;
	}
	struct sockaddr_un a = { .sun_family = AF_UNIX };
	char *p = a.sun_path + 1;
	memcpy(p, "tcs-idioms-", 11);
	p = put_int(p + 11, getpid());
	*p++ = '-';
	p = put_int(p, c->who);
	*p++ = '-';
	p = put_int(p, c->f->round);
	socklen_t len = (socklen_t)(p - (char *)&a);
	if (bind(s, (struct sockaddr *)&a, len) != 0) {
		fail(c, "bind", errno);
		close(s);
		return;
	}
	struct sockaddr_un got;
	socklen_t got_len = sizeof got;
	if (getsockname(s, (struct sockaddr *)&got, &got_len) != 0)
		fail(c, "getsockname", errno);
	else
		check(c, got_len == len && memcmp(&got, &a, len) == 0, "name");
	int size = 65536, back = 0;
	socklen_t back_len = sizeof back;
	if (setsockopt(s, SOL_SOCKET, SO_SNDBUF, &size, sizeof size) != 0)
		fail(c, "setsockopt", errno);
	if (getsockopt(s, SOL_SOCKET, SO_SNDBUF, &back, &back_len) != 0)
		fail(c, "getsockopt", errno);
	else
		check(c, back >= size, "sndbuf");
	char b = 0;
	if (sendto(s, "x", 1, 0, (struct sockaddr *)&a, len) != 1)
		fail(c, "sendto", errno);
	else if (recvfrom(s, &b, 1, 0, NULL, NULL) != 1 || b != 'x')
		fail(c, "recvfrom", errno);
	if (connect(s, (struct sockaddr *)&a, len) != 0)
		fail(c, "connect", errno);
	else if (send(s, "y", 1, 0) != 1)
		fail(c, "send", errno);
	else if (recv(s, &b, 1, 0) != 1 || b != 'y')
		fail(c, "recv", errno);
	struct iovec io = { .iov_base = "z", .iov_len = 1 };
	struct msghdr m = { .msg_iov = &io, .msg_iovlen = 1 };
	if (sendmsg(s, &m, 0) != 1) {
		fail(c, "sendmsg", errno);
	} else {
		io.iov_base = &b;
		if (recvmsg(s, &m, 0) != 1 || b != 'z')
			fail(c, "recvmsg", errno);
	}
	if (close(s) != 0)
		fail(c, "close", errno);
}

/* A pseudo-terminal's master, as a serial port's code treats its tty. */
void c_tcattr(struct ctx *c)
{
	int fd = open("/dev/ptmx", O_RDWR | O_NOCTTY | O_CLOEXEC);
	if (fd < 0) {
		fail(c, "open", errno);
		return;
	}
	struct termios t;
	if (tcgetattr(fd, &t) != 0)
		fail(c, "tcgetattr", errno);
	else if (tcsetattr(fd, TCSANOW, &t) != 0)
		fail(c, "tcsetattr", errno);
	if (tcflush(fd, TCIOFLUSH) != 0)
		fail(c, "tcflush", errno);
	/* (tcdrain waits: a signal may interrupt it, and it is asked again) */
	int r;
	while ((r = tcdrain(fd)) != 0 && errno == EINTR)
		interrupted();
	if (r != 0)
		fail(c, "tcdrain", errno);
	if (close(fd) != 0)
		fail(c, "close", errno);
}

/* dup, dup2 and dup3 of the flow's pipe, onto numbers of its own. */
void c_dup(struct ctx *c)
{
	int base = 700 + 10 * c->who;
	int a = dup(c->f->pipe_w);
	if (a < 0) {
		fail(c, "dup", errno);
		return;
	}
	check(c, dup2(a, base) == base, "dup2");
	check(c, dup3(a, base + 1, O_CLOEXEC) == base + 1, "dup3");
	check(c, (fcntl(base + 1, F_GETFD) & FD_CLOEXEC) != 0, "cloexec");
	check(c, close(base + 1) == 0 && close(base) == 0 && close(a) == 0, "close");
}

/* writev, ioctl(FIONREAD), readv on a pipe of its own. */
void c_pipe_io(struct ctx *c)
{
	int p[2];
	if (pipe2(p, O_CLOEXEC) != 0) {
		fail(c, "pipe", errno);
		return;
	}
	struct iovec out[2] = { { "ab", 2 }, { "cd", 2 } };
	check(c, writev(p[1], out, 2) == 4, "writev");
	int queued = -1;
	if (ioctl(p[0], FIONREAD, &queued) != 0)
		fail(c, "ioctl", errno);
	else
		check(c, queued == 4, "fionread");
	char x[2], y[2];
	struct iovec in[2] = { { x, 2 }, { y, 2 } };
	check(c, readv(p[0], in, 2) == 4 && memcmp(x, "ab", 2) == 0 && memcmp(y, "cd", 2) == 0, "readv");
	check(c, close(p[0]) == 0 && close(p[1]) == 0, "close");
}

/* close_range of one descriptor, closefrom of everything from a high one
 * on (what daemons do, and tcs's own descriptors must survive). */
void c_close_range(struct ctx *c)
{
	int fd = 800 + c->who;
	if (dup2(c->f->pipe_w, fd) != fd) {
		fail(c, "dup2", errno);
		return;
	}
	if (close_range(fd, fd, 0) != 0)
		fail(c, "close_range", errno);
	check(c, fcntl(fd, F_GETFD) == -1 && errno == EBADF, "still_open");
	if (dup2(c->f->pipe_w, fd) != fd) {
		fail(c, "dup2", errno);
		return;
	}
	closefrom(fd);
	check(c, fcntl(fd, F_GETFD) == -1 && errno == EBADF, "closefrom");
}

/* The thread's timer slack, read and set to what it was: under tcs it is
 * what the thread would have natively (docs/DESIGN.md §2). */
void c_prctl(struct ctx *c)
{
	int v = prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0);
	if (v < 0) {
		fail(c, "prctl", errno);
		return;
	}
	if (prctl(PR_SET_TIMERSLACK, (unsigned long)v, 0, 0, 0) != 0)
		fail(c, "prctl_set", errno);
	check(c, prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0) == v, "changed");
	__atomic_store_n(&S.slack, v, __ATOMIC_SEQ_CST);
}
