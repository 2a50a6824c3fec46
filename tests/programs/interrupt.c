/* interrupt: POSIX semantics of waits that a signal handler interrupts.
 * A one-shot interval timer (50 ms of virtual time: tcs keeps setitimer's)
 * fires SIGALRM while the program waits forever. Prints one key=value line
 * per check; for the sleeps, how long they slept by what they say is left
 * (*_slept_ns), and how much virtual time arming the timer took
 * (arm_window_ns: the timer started within it). */
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/select.h>
#include <sys/time.h>
#include <threads.h>
#include <time.h>
#include <unistd.h>

#include "work.h"

static volatile sig_atomic_t handled;

static void on_alarm(int sig)
{
	(void)sig;
	handled++;
}

/* Arms the 50 ms timer; returns the virtual time the arming took. */
static long long arm(void)
{
	struct itimerval it = { { 0, 0 }, { 0, 50000 } };
	long long before = clock_ns(CLOCK_MONOTONIC);
	setitimer(ITIMER_REAL, &it, NULL);
	return clock_ns(CLOCK_MONOTONIC) - before;
}

/* What a sleep of `asked` slept, by the `rem` it left (asked is 2^40 s:
 * in ns it does not fit in 64 bits, the difference does). */
static long long slept_ns(struct timespec asked, struct timespec rem)
{
	return (long long)(asked.tv_sec - rem.tv_sec) * 1000000000LL + (asked.tv_nsec - rem.tv_nsec);
}

int main(void)
{
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_alarm;
	sa.sa_flags = SA_RESTART; /* nanosleep and poll fail with EINTR even so */
	sigaction(SIGALRM, &sa, NULL);
	/* The calls arm() times, once before: a function's first call binds it
	 * (the dynamic linker's work, tens of microseconds of CPU). */
	struct itimerval off = { { 0, 0 }, { 0, 0 } };
	setitimer(ITIMER_REAL, &off, NULL);
	clock_ns(CLOCK_MONOTONIC);

	long long window = arm();
	struct timespec forever = { (time_t)1 << 40, 0 }, rem = { 0, 0 };
	int r = nanosleep(&forever, &rem);
	printf("nanosleep=%d errno=%s handled=%d nanosleep_slept_ns=%lld nanosleep_arm_window_ns=%lld\n", r,
	       r ? strerrorname_np(errno) : "0", (int)handled, slept_ns(forever, rem), window);

	window = arm();
	rem = (struct timespec){ 0, 0 };
	int cr = clock_nanosleep(CLOCK_MONOTONIC, 0, &forever, &rem);
	printf("clock_nanosleep=%s handled=%d clock_nanosleep_slept_ns=%lld clock_nanosleep_arm_window_ns=%lld\n",
	       cr ? strerrorname_np(cr) : "0", (int)handled, slept_ns(forever, rem), window);

	arm();
	errno = 0;
	r = poll(NULL, 0, -1);
	printf("poll=%d errno=%s handled=%d\n", r, strerrorname_np(errno), (int)handled);

	arm();
	int ep = epoll_create1(0);
	struct epoll_event ev;
	r = epoll_wait(ep, &ev, 1, -1);
	printf("epoll_wait=%d errno=%s handled=%d\n", r, strerrorname_np(errno), (int)handled);

	arm();
	r = select(0, NULL, NULL, NULL, NULL);
	printf("select=%d errno=%s handled=%d\n", r, strerrorname_np(errno), (int)handled);

	/* The variants with a signal mask of their own: SIGALRM blocked
	 * outside them, their empty mask lets it in (their reason to be);
	 * 10 s time-outs, which a wait that ignored its mask would reach. */
	sigset_t none, alarm_only;
	sigemptyset(&none);
	sigemptyset(&alarm_only);
	sigaddset(&alarm_only, SIGALRM);
	sigprocmask(SIG_BLOCK, &alarm_only, NULL);
	struct timespec ten = { 10, 0 };
	arm();
	errno = 0;
	r = ppoll(NULL, 0, &ten, &none);
	printf("ppoll=%d errno=%s handled=%d\n", r, strerrorname_np(errno), (int)handled);

	arm();
	errno = 0;
	r = pselect(0, NULL, NULL, NULL, &ten, &none);
	printf("pselect=%d errno=%s handled=%d\n", r, strerrorname_np(errno), (int)handled);

	arm();
	errno = 0;
	r = epoll_pwait(ep, &ev, 1, 10000, &none);
	printf("epoll_pwait=%d errno=%s handled=%d\n", r, strerrorname_np(errno), (int)handled);

	arm();
	errno = 0;
	r = epoll_pwait2(ep, &ev, 1, &ten, &none);
	printf("epoll_pwait2=%d errno=%s handled=%d\n", r, strerrorname_np(errno), (int)handled);
	sigprocmask(SIG_UNBLOCK, &alarm_only, NULL);

	/* An absolute sleep, and C11's. */
	arm();
	struct timespec far;
	clock_gettime(CLOCK_MONOTONIC, &far);
	far.tv_sec += 1000000;
	cr = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &far, NULL);
	printf("clock_nanosleep_abs=%s handled=%d\n", cr ? strerrorname_np(cr) : "0", (int)handled);

	window = arm();
	rem = (struct timespec){ 0, 0 };
	r = thrd_sleep(&forever, &rem);
	printf("thrd_sleep=%d handled=%d thrd_sleep_slept_ns=%lld thrd_sleep_arm_window_ns=%lld\n", r, (int)handled,
	       slept_ns(forever, rem), window);

	/* After all that, plain timed waits still end on virtual schedule. */
	struct timespec a, b;
	clock_gettime(CLOCK_MONOTONIC, &a);
	unsigned left = sleep(1);
	clock_gettime(CLOCK_MONOTONIC, &b);
	printf("sleep_left=%u slept_ns=%lld\n", left, (b.tv_sec - a.tv_sec) * 1000000000LL + (b.tv_nsec - a.tv_nsec));
	return 0;
}
