/* Signals: kill, killpg, sigqueue, tgkill, pidfd_send_signal (and their
 * numbers through syscall()), pthread_kill and pthread_sigqueue. The
 * kernel delivers them as always; the coordinator is told whom they are
 * for (protocol.h, TCS_MSG_KILL), so that a controller waiting in virtual
 * time acts on one at the sender's time rather than whenever the
 * coordinator next gives it the core: before the send for another process,
 * after it for one's own (a thread of it may be waiting; wait.h says why).
 * Sent from a signal handler that runs inside one of our waits (coreutils
 * timeout kills its child from its SIGALRM handler), the news waits until
 * that wait is left (tcs_signal_sending, wait.c). */
#include <pthread.h>
#include <signal.h>

#include "raw_syscall.h"
#include "real.h"
#include "wait.h"

/* The kernel's result r of sending sig to target (thread tid, or 0), told
 * to the coordinator if it reached this process. */
static long tcs_sent(long target, long tid, int sig, long r)
{
	if (r == 0)
		tcs_signal_sent(target, tid, sig);
	return r;
}

TCS_EXPORT int kill(pid_t pid, int sig)
{
	tcs_signal_sending(pid, sig);
	return tcs_errno_result(tcs_sent(pid, 0, sig, tcs_sys2(SYS_kill, pid, sig)));
}

TCS_EXPORT int killpg(pid_t group, int sig)
{
	if (group < 0)
		return tcs_errno_result(-EINVAL);
	tcs_signal_sending(-(long)group, sig);
	return tcs_errno_result(tcs_sent(-(long)group, 0, sig, tcs_sys2(SYS_kill, -group, sig)));
}

TCS_EXPORT int tgkill(pid_t tgid, pid_t tid, int sig)
{
	tcs_signal_sending(tgid, sig);
	return tcs_errno_result(tcs_sent(tgid, tid, sig, tcs_sys3(SYS_tgkill, tgid, tid, sig)));
}

/* glibc sends these with its own tgkill system call, not through ours. */
TCS_EXPORT int pthread_kill(pthread_t thread, int sig)
{
	int r = tcs_real()->pthread_kill(thread, sig);
	if (r == 0 && !pthread_equal(thread, pthread_self()))
		tcs_signal_sent(0, 0, sig);
	return r;
}

TCS_EXPORT int pthread_sigqueue(pthread_t thread, int sig, const union sigval value)
{
	int r = tcs_real()->pthread_sigqueue(thread, sig, value);
	if (r == 0 && !pthread_equal(thread, pthread_self()))
		tcs_signal_sent(0, 0, sig);
	return r;
}

TCS_EXPORT int sigqueue(pid_t pid, int sig, const union sigval value)
{
	/* What glibc sends: the sender's pid and uid, SI_QUEUE, the value. */
	siginfo_t info;
	__builtin_memset(&info, 0, sizeof info);
	info.si_signo = sig;
	info.si_code = SI_QUEUE;
	info.si_pid = (pid_t)tcs_sys0(SYS_getpid);
	info.si_uid = (uid_t)tcs_sys0(SYS_getuid);
	info.si_value = value;
	tcs_signal_sending(pid, sig);
	return tcs_errno_result(tcs_sent(pid, 0, sig, tcs_sys3(SYS_rt_sigqueueinfo, pid, sig, &info)));
}

/* (Declared by no header of this glibc.) */
TCS_EXPORT int pidfd_send_signal(int pidfd, int sig, siginfo_t *info, unsigned flags);
TCS_EXPORT int pidfd_send_signal(int pidfd, int sig, siginfo_t *info, unsigned flags)
{
	tcs_signal_sending(-1, sig);
	return tcs_errno_result(tcs_sent(-1, 0, sig, tcs_sys4(SYS_pidfd_send_signal, pidfd, sig, info, flags)));
}
