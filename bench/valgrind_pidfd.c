/* valgrind_pidfd.so: lets tcs-run run under valgrind 3.19 (Debian 12's),
 * which does not know pidfd_open (system call 434) and fails it. Preloaded
 * into tcs-run, it answers pidfd_open with a pipe that a thread of its own
 * makes readable when the process exits (as a pidfd becomes readable), and
 * waitid(P_PIDFD, fd) with waitid(P_PID, the pid). A measuring aid, never
 * part of a run (docs/PERFORMANCE.md, "Trace and record"):
 *
 *   LD_PRELOAD=$PWD/build/bench/valgrind_pidfd.so valgrind --tool=callgrind \
 *       build/tools/tcs-run -m cpu -d 2s build/examples/pendulum_pd
 *
 * Only tcs-run's own children are watched (waitid needs them), and it takes
 * itself out of LD_PRELOAD so that the controllers tcs-run starts do not
 * load it. */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE
#endif
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#define SELF "valgrind_pidfd.so"
#define MAX_FD 4096

static pid_t pid_of_fd[MAX_FD];

struct watch {
	pid_t pid;
	int write_end;
};

static void *watch_exit(void *arg)
{
	struct watch *w = arg;
	siginfo_t si;
	/* WNOWAIT: the exit stays for tcs-run's own waitid to reap. */
	while (waitid(P_PID, (id_t)w->pid, &si, WEXITED | WNOWAIT) != 0 && errno == EINTR)
		;
	char b = 1;
	(void)!write(w->write_end, &b, 1);
	free(w);
	return NULL;
}

static long pidfd_open_by_pipe(pid_t pid)
{
	int p[2];
	if (pipe2(p, O_CLOEXEC) < 0)
		return -1;
	struct watch *w = malloc(sizeof *w);
	if (!w || p[0] >= MAX_FD) {
		free(w);
		close(p[0]);
		close(p[1]);
		errno = EMFILE;
		return -1;
	}
	w->pid = pid;
	w->write_end = p[1];
	pid_of_fd[p[0]] = pid;
	pthread_t t;
	if (pthread_create(&t, NULL, watch_exit, w) != 0) {
		free(w);
		close(p[0]);
		close(p[1]);
		errno = EAGAIN;
		return -1;
	}
	pthread_detach(t);
	return p[0];
}

long syscall(long nr, ...)
{
	va_list ap;
	va_start(ap, nr);
	long a[6];
	for (int i = 0; i < 6; i++)
		a[i] = va_arg(ap, long);
	va_end(ap);
	if (nr == SYS_pidfd_open)
		return pidfd_open_by_pipe((pid_t)a[0]);
	static long (*real)(long, ...);
	if (!real)
		real = (long (*)(long, ...))dlsym(RTLD_NEXT, "syscall");
	return real(nr, a[0], a[1], a[2], a[3], a[4], a[5]);
}

int waitid(idtype_t type, id_t id, siginfo_t *si, int options)
{
	static int (*real)(idtype_t, id_t, siginfo_t *, int);
	if (!real)
		real = (int (*)(idtype_t, id_t, siginfo_t *, int))dlsym(RTLD_NEXT, "waitid");
	if (type == P_PIDFD && id < MAX_FD && pid_of_fd[id])
		return real(P_PID, (id_t)pid_of_fd[id], si, options);
	return real(type, id, si, options);
}

/* In tcs-run only (valgrind's own launcher is a shell script that loads it
 * first): out of the LD_PRELOAD its controllers inherit. */
__attribute__((constructor)) static void leave_ld_preload(void)
{
	extern char **environ;
	if (strcmp(program_invocation_short_name, "tcs-run") != 0)
		return;
	for (char **e = environ; e && *e; e++) {
		if (strncmp(*e, "LD_PRELOAD=", 11) != 0)
			continue;
		/* Each entry of the list that ends in SELF, with its separator. */
		char *s = *e + 11;
		for (char *at = s; (at = strstr(at, SELF)) != NULL;) {
			char *start = at;
			while (start > s && start[-1] != ':' && start[-1] != ' ')
				start--;
			char *end = at + strlen(SELF);
			if (*end == ':' || *end == ' ')
				end++;
			memmove(start, end, strlen(end) + 1);
			at = start;
		}
		size_t n = strlen(s);
		while (n > 0 && (s[n - 1] == ':' || s[n - 1] == ' '))
			s[--n] = '\0';
	}
}
