/* Signals to other processes: kill, killpg, sigqueue, tgkill,
 * pidfd_send_signal (and their numbers through syscall()). The kernel
 * delivers them as always; the coordinator is told first whom they are for
 * (protocol.h, TCS_MSG_KILL), so that a controller waiting in virtual time
 * acts on one at the sender's time rather than whenever the coordinator
 * next gives it the core. Sent from a signal handler that runs inside one
 * of our waits (coreutils timeout kills its child from its SIGALRM
 * handler), the news waits until that wait is left (tcs_signal_sending,
 * wait.c). */
#include <signal.h>

#include "raw_syscall.h"
#include "wait.h"

TCS_EXPORT int kill(pid_t pid, int sig)
{
	tcs_signal_sending(pid, sig);
	return tcs_errno_result(tcs_sys2(SYS_kill, pid, sig));
}

TCS_EXPORT int killpg(pid_t group, int sig)
{
	if (group < 0)
		return tcs_errno_result(-EINVAL);
	tcs_signal_sending(-(long)group, sig);
	return tcs_errno_result(tcs_sys2(SYS_kill, -group, sig));
}

TCS_EXPORT int tgkill(pid_t tgid, pid_t tid, int sig)
{
	tcs_signal_sending(tgid, sig);
	return tcs_errno_result(tcs_sys3(SYS_tgkill, tgid, tid, sig));
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
	return tcs_errno_result(tcs_sys3(SYS_rt_sigqueueinfo, pid, sig, &info));
}

/* (Declared by no header of this glibc.) */
TCS_EXPORT int pidfd_send_signal(int pidfd, int sig, siginfo_t *info, unsigned flags);
TCS_EXPORT int pidfd_send_signal(int pidfd, int sig, siginfo_t *info, unsigned flags)
{
	tcs_signal_sending(-1, sig);
	return tcs_errno_result(tcs_sys4(SYS_pidfd_send_signal, pidfd, sig, info, flags));
}
