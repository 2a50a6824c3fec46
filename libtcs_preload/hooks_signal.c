/* Signals to other processes: kill, killpg, sigqueue, tgkill,
 * pidfd_send_signal (and their numbers through syscall()). The kernel
 * delivers them as always; the coordinator is then told whom they reached
 * (protocol.h, TCS_MSG_KILL), so that a controller waiting in virtual time
 * acts on one at the sender's time rather than whenever the coordinator
 * next gives it the core. Sent from a signal handler that runs inside one
 * of our waits (coreutils timeout kills its child from its SIGALRM
 * handler), the news waits until that wait is left (tcs_wait_leave). */
#include <signal.h>

#include "preload.h"
#include "raw_syscall.h"

/* Targets told from inside a wait, per thread (a handler runs on the
 * thread whose wait it interrupted). More than fit: tell "everyone". */
#define TCS_MAX_PENDING_KILLS 8
static __thread long tcs_pending_kills[TCS_MAX_PENDING_KILLS];
__thread volatile int tcs_npending_kills;

static void tcs_send_kill(long target)
{
	struct tcs_msg m = tcs_msg_make(TCS_MSG_KILL, 0), w;
	m.arg = target;
	m.v = tcs_vnow();
	m.cpu = tcs_charge_point();
	tcs_roundtrip(&m, NULL, 0, NULL, &w, NULL);
}

/* Inside a wait, as it is left (tcs_wait_enter() still held): what
 * handlers that ran in it left to tell. */
void tcs_flush_kills(void)
{
	while (tcs_npending_kills > 0) {
		long target = tcs_pending_kills[tcs_npending_kills - 1];
		tcs_npending_kills--;
		tcs_send_kill(target);
	}
}

static void tcs_tell_kill(long target)
{
	if (!tcs_active())
		return;
	if (tcs_wait_enter()) {
		tcs_send_kill(target);
		tcs_wait_leave();
		return;
	}
	int n = tcs_npending_kills;
	for (int i = 0; i < n; i++)
		if (tcs_pending_kills[i] == target)
			return;
	if (n == TCS_MAX_PENDING_KILLS) {
		tcs_pending_kills[0] = -1;
		tcs_npending_kills = 1;
		return;
	}
	tcs_pending_kills[n] = target;
	tcs_npending_kills = n + 1;
}

/* After a successful send of sig to `target` (kill's convention). */
static long tcs_after_kill(long r, long target, int sig)
{
	if (r == 0 && sig != 0 && target != tcs_rt.pid)
		tcs_tell_kill(target);
	return r;
}

long tcs_signal_syscall(long nr, const long a[6])
{
	long r = tcs_sys6(nr, a[0], a[1], a[2], a[3], a[4], a[5]);
	switch (nr) {
	case SYS_kill:
	case SYS_rt_sigqueueinfo:
		return tcs_after_kill(r, a[0], (int)a[1]);
	case SYS_tgkill:
		return tcs_after_kill(r, a[0], (int)a[2]);
	default: /* tkill, pidfd_send_signal: the process is not at hand */
		return tcs_after_kill(r, -1, (int)a[1]);
	}
}

TCS_EXPORT int kill(pid_t pid, int sig)
{
	return tcs_errno_result(tcs_after_kill(tcs_sys2(SYS_kill, pid, sig), pid, sig));
}

TCS_EXPORT int killpg(pid_t group, int sig)
{
	if (group < 0)
		return tcs_errno_result(-EINVAL);
	return tcs_errno_result(tcs_after_kill(tcs_sys2(SYS_kill, -group, sig), -(long)group, sig));
}

TCS_EXPORT int tgkill(pid_t tgid, pid_t tid, int sig)
{
	return tcs_errno_result(tcs_after_kill(tcs_sys3(SYS_tgkill, tgid, tid, sig), tgid, sig));
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
	return tcs_errno_result(tcs_after_kill(tcs_sys3(SYS_rt_sigqueueinfo, pid, sig, &info), pid, sig));
}

TCS_EXPORT int pidfd_send_signal(int pidfd, int sig, siginfo_t *info, unsigned flags)
{
	return tcs_errno_result(tcs_after_kill(tcs_sys4(SYS_pidfd_send_signal, pidfd, sig, info, flags), -1, sig));
}
