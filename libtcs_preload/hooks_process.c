/* Process hooks: fork, vfork, posix_spawn, posix_spawnp, system, and the
 * wait family (wait, waitpid, wait3, wait4, waitid). A child of a
 * controller registers with the coordinator before it runs on (child.c):
 * a forked one in the fork's child handler, one started by vfork or
 * posix_spawn when its new program loads (its clock page is then its
 * parent's); the parent waits here for that in each case. A parent
 * waiting for a child waits in virtual time: the coordinator wakes it when
 * a child of its exits. */
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include "cpu_estimate.h"
#include "raw_syscall.h"
#include "real.h"
#include "roundtrip.h"
#include "vclock.h"
#include "wait.h"

extern char **environ;

/* The parent of a new child waits until the child has registered (or can
 * be seen never to: a static program, LD_PRELOAD gone; or has died), so
 * that no virtual time passes in which the child is not counted: a forked
 * child registers in its fork handler (under SCHED_FIFO on their one core
 * it runs only once the parent waits), one started by vfork or
 * posix_spawn once its new program has loaded. */
static void tcs_await_child(pid_t pid)
{
	if (pid <= 0 || !tcs_active() || !tcs_wait_enter())
		return;
	struct tcs_msg m = tcs_msg_make(TCS_MSG_CHILD, 0), w;
	m.arg = pid;
	m.flags = TCS_CHILD_PARENT;
	m.cpu = tcs_charge_point(TCS_MSG_CHILD);
	__atomic_store_n(&tcs_rt.page->fork_claim, m.cpu, __ATOMIC_RELAXED);
	tcs_roundtrip(&m, NULL, 0, NULL, &w, NULL);
	tcs_wait_leave();
}

TCS_EXPORT pid_t fork(void)
{
	pid_t (*real_fork)(void) = tcs_real()->fork;
	if (!real_fork)
		return (pid_t)tcs_errno_result(-ENOSYS);
	pid_t pid = real_fork();
	tcs_await_child(pid);
	return pid;
}

typedef int (*tcs_spawn_fn)(pid_t *, const char *, const posix_spawn_file_actions_t *, const posix_spawnattr_t *,
			    char *const[], char *const[]);

static int tcs_spawn(tcs_spawn_fn real, pid_t *pid, const char *file, const posix_spawn_file_actions_t *actions,
		     const posix_spawnattr_t *attr, char *const argv[], char *const envp[])
{
	if (!real)
		return ENOSYS;
	pid_t child = -1;
	int r = real(&child, file, actions, attr, argv, envp);
	if (r == 0) {
		if (pid)
			*pid = child;
		tcs_await_child(child);
	}
	return r;
}

TCS_EXPORT int posix_spawn(pid_t *pid, const char *path, const posix_spawn_file_actions_t *actions,
			   const posix_spawnattr_t *attr, char *const argv[], char *const envp[])
{
	return tcs_spawn(tcs_real()->posix_spawn, pid, path, actions, attr, argv, envp);
}

TCS_EXPORT int posix_spawnp(pid_t *pid, const char *file, const posix_spawn_file_actions_t *actions,
			    const posix_spawnattr_t *attr, char *const argv[], char *const envp[])
{
	return tcs_spawn(tcs_real()->posix_spawnp, pid, file, actions, attr, argv, envp);
}

#if defined(__x86_64__)
/* vfork: the child borrows the parent's memory, stack included, until it
 * execs or exits, so no C function may return in it. As glibc's own, the
 * return address is kept in a register across the system call (each
 * process has its registers); the parent then, the child gone from its
 * stack, waits for the child's registration in C. Elsewhere vfork is
 * libc's and the child is counted from when its program loads. */
long tcs_after_vfork(long pid) __attribute__((used));
long tcs_after_vfork(long pid)
{
	/* The child ran on our memory, this thread's CPU anchor included,
	 * with readings of its own CPU clock; and we were suspended meanwhile,
	 * which the TSC since our last reading would count as our CPU. */
	tcs_anchor.valid = 0;
	tcs_anchor.v_valid = 0;
	if (pid < 0)
		return tcs_errno_result(pid);
	tcs_await_child((pid_t)pid);
	return pid;
}

__asm__(".text\n"
	".globl vfork\n"
	".type vfork, @function\n"
	"vfork:\n"
	"	popq %rdi\n" /* the return address, out of the shared stack */
	"	movl $58, %eax\n" /* SYS_vfork */
	"	syscall\n"
	"	pushq %rdi\n"
	"	testq %rax, %rax\n"
	"	jz 1f\n" /* the child: straight back */
	"	movq %rax, %rdi\n"
	"	subq $8, %rsp\n" /* the stack 16-byte aligned at the call */
	"	call tcs_after_vfork@PLT\n"
	"	addq $8, %rsp\n"
	"1:	ret\n"
	".size vfork, .-vfork\n");
#endif

/* ---- waiting for children -------------------------------------------------- */

/* A wait for a child: tried without blocking; while none is there, waits in
 * virtual time until a child ends (and looks again every 100 ms). */
static long tcs_wait_child(idtype_t type, id_t id, siginfo_t *info, int options, struct rusage *ru, int *status,
			   int as_wait4)
{
	for (;;) {
		long r;
		siginfo_t si;
		if (as_wait4) {
			r = tcs_sys4(SYS_wait4, type == P_PID ? (long)id : type == P_PGID ? -(long)id : -1, status,
				     options | WNOHANG, ru);
		} else {
			__builtin_memset(&si, 0, sizeof si);
			r = tcs_sys5(SYS_waitid, type, id, &si, options | WNOHANG, ru);
			if (r == 0 && info)
				*info = si;
			if (r == 0 && si.si_pid != 0)
				return 0;
			if (r == 0 && (options & WNOHANG))
				return 0;
		}
		if (r != 0 && (as_wait4 || r < 0))
			return r;
		if (as_wait4 && (options & WNOHANG))
			return 0;
		if (!tcs_wait_enter())
			return as_wait4 ? tcs_sys4(SYS_wait4, type == P_PID ? (long)id : -1, status, options, ru)
					: tcs_sys5(SYS_waitid, type, id, info, options, ru);
		/* A child started by vfork or posix_spawn registers when its new
		 * program loads; under SCHED_FIFO on our one core it runs only if
		 * we step back (our answer may come without our ever blocking). */
		tcs_sys0(SYS_sched_yield);
		/* Woken when a child ends, at its virtual time (a child in real
		 * time, outside tcs, is looked for at each step: the coordinator's
		 * re-check). No time-out of our own: one could find a child ended
		 * in the kernel that has not ended yet in virtual time. A stop or
		 * continue is no news of the coordinator's: waits for those look
		 * every 100 ms. */
		int changes = options & (WUNTRACED | WCONTINUED);
		struct tcs_wait_time t = { changes ? 100 * TCS_NS_PER_MS : TCS_NEVER, changes != 0, 0, 0, 0, 0 };
		long w = tcs_wait(&t, TCS_BLOCK_POLL, TCS_BLOCK_CHILD, NULL, 0, NULL);
		tcs_wait_leave();
		if (w == -EINTR)
			return -EINTR;
	}
}

TCS_EXPORT pid_t wait4(pid_t pid, int *status, int options, struct rusage *ru)
{
	if (!tcs_active())
		return (pid_t)tcs_errno_result(tcs_sys4(SYS_wait4, pid, status, options, ru));
	idtype_t type = pid > 0 ? P_PID : pid < -1 ? P_PGID : P_ALL;
	/* (pid 0, "my process group", is waited for as any child.) */
	return (pid_t)tcs_errno_result(
		tcs_wait_child(type, (id_t)(pid < -1 ? -pid : pid > 0 ? pid : 0), NULL, options, ru, status, 1));
}

TCS_EXPORT pid_t waitpid(pid_t pid, int *status, int options)
{
	return wait4(pid, status, options, NULL);
}

TCS_EXPORT pid_t wait(int *status)
{
	return wait4(-1, status, 0, NULL);
}

TCS_EXPORT pid_t wait3(int *status, int options, struct rusage *ru)
{
	return wait4(-1, status, options, ru);
}

TCS_EXPORT int waitid(idtype_t type, id_t id, siginfo_t *info, int options)
{
	if (!tcs_active())
		return tcs_errno_result(tcs_sys5(SYS_waitid, type, id, info, options, NULL));
	return tcs_errno_result(tcs_wait_child(type, id, info, options, NULL, NULL, 0));
}

/* system: glibc's waits for its shell with an internal call no preload sees
 * (the parent would sleep in the kernel where tcs cannot tell it waits), so
 * it is done here, as POSIX describes it: the shell started with
 * posix_spawn, SIGINT and SIGQUIT ignored and SIGCHLD blocked meanwhile. */
TCS_EXPORT int system(const char *command)
{
	if (!tcs_active()) {
		int (*real_system)(const char *) = tcs_real()->system;
		return real_system ? real_system(command) : tcs_errno_result(-ENOSYS);
	}
	if (!command)
		return 1; /* a shell is there */
	struct sigaction ignore, old_int, old_quit;
	__builtin_memset(&ignore, 0, sizeof ignore);
	ignore.sa_handler = SIG_IGN;
	sigaction(SIGINT, &ignore, &old_int);
	sigaction(SIGQUIT, &ignore, &old_quit);
	sigset_t chld, old_mask;
	sigemptyset(&chld);
	sigaddset(&chld, SIGCHLD);
	sigprocmask(SIG_BLOCK, &chld, &old_mask);

	posix_spawnattr_t attr;
	posix_spawnattr_init(&attr);
	sigset_t defaults;
	sigemptyset(&defaults);
	if (old_int.sa_handler != SIG_IGN)
		sigaddset(&defaults, SIGINT);
	if (old_quit.sa_handler != SIG_IGN)
		sigaddset(&defaults, SIGQUIT);
	posix_spawnattr_setsigdefault(&attr, &defaults);
	posix_spawnattr_setsigmask(&attr, &old_mask);
	posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
	char *argv[] = { (char *)"sh", (char *)"-c", (char *)command, NULL };
	pid_t pid;
	int status;
	int err = posix_spawn(&pid, "/bin/sh", NULL, &attr, argv, environ);
	posix_spawnattr_destroy(&attr);
	if (err != 0) {
		status = W_EXITCODE(127, 0);
	} else {
		long r;
		do
			r = tcs_wait_child(P_PID, (id_t)pid, NULL, 0, NULL, &status, 1);
		while (r == -EINTR);
		if (r < 0)
			status = -1;
	}
	sigaction(SIGINT, &old_int, NULL);
	sigaction(SIGQUIT, &old_quit, NULL);
	sigprocmask(SIG_SETMASK, &old_mask, NULL);
	return status;
}
