/* interrupt: POSIX semantics of waits that a real signal handler interrupts.
 * A real-time interval timer (setitimer is not virtualised yet) fires
 * SIGALRM while the program waits forever, so virtual time idles at real
 * speed until the signal comes. Prints one key=value line per check. */
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/select.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

static volatile sig_atomic_t handled;

static void on_alarm(int sig)
{
	(void)sig;
	handled++;
}

static void arm(void)
{
	struct itimerval it = { { 0, 0 }, { 0, 50000 } };
	setitimer(ITIMER_REAL, &it, NULL);
}

int main(void)
{
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_alarm;
	sa.sa_flags = SA_RESTART; /* nanosleep and poll fail with EINTR even so */
	sigaction(SIGALRM, &sa, NULL);

	arm();
	struct timespec forever = { (time_t)1 << 40, 0 }, rem = { 0, 0 };
	int r = nanosleep(&forever, &rem);
	printf("nanosleep=%d errno=%s rem_large=%d handled=%d\n", r, r ? strerrorname_np(errno) : "0",
	       rem.tv_sec > ((time_t)1 << 39), (int)handled);

	arm();
	int cr = clock_nanosleep(CLOCK_MONOTONIC, 0, &forever, &rem);
	printf("clock_nanosleep=%s handled=%d\n", cr ? strerrorname_np(cr) : "0", (int)handled);

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

	/* After all that, plain timed waits still end on virtual schedule. */
	struct timespec a, b;
	clock_gettime(CLOCK_MONOTONIC, &a);
	unsigned left = sleep(1);
	clock_gettime(CLOCK_MONOTONIC, &b);
	printf("sleep_left=%u slept_ns=%lld\n", left, (b.tv_sec - a.tv_sec) * 1000000000LL + (b.tv_nsec - a.tv_nsec));
	return 0;
}
