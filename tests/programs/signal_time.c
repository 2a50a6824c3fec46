/* signal_time HOW: a signal sent 3 ms (and the sleep's timer slack) after
 * the start to a receiver asleep for 1 s, whose SIGUSR1 handler reads
 * CLOCK_MONOTONIC. HOW is who sends it and how:
 *   sigqueue  a forked child, sigqueue(parent, SIGUSR1, 42)
 *   tgkill    a forked child, tgkill(parent, parent, SIGUSR1)
 *   thread_tgkill    a second thread, tgkill to the main thread
 *   thread_sigqueue  a second thread (SIGUSR1 blocked in it), sigqueue to
 *                    its own process
 * Prints key=value lines, times in ns since the receiver's start (read
 * before the sender began): when the sender sent (sent, read just before
 * the send), when the handler ran (handled), the value it got (value: -1
 * if none), how the sleep ended (sleep_errno) and what it had left
 * (left), and when it returned (woke). */
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static long long t0;
static volatile long long handled = -1;
static volatile int value = -1;
static long long *sent; /* shared with a forked sender */
static pid_t main_tid;
static const char *how;

static long long mono(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec * 1000000000LL + t.tv_nsec;
}

static void on_usr1(int sig, siginfo_t *si, void *uc)
{
	(void)sig, (void)uc;
	handled = mono() - t0;
	if (si->si_code == SI_QUEUE)
		value = si->si_value.sival_int;
}

/* The sender: 3 ms asleep, the send, 3 ms asleep again. */
static void send_it(void)
{
	struct timespec d = { 0, 3000000 };
	nanosleep(&d, NULL);
	union sigval v = { .sival_int = 42 };
	*sent = mono() - t0;
	if (strcmp(how, "sigqueue") == 0)
		sigqueue(getppid(), SIGUSR1, v);
	else if (strcmp(how, "tgkill") == 0)
		tgkill(getppid(), getppid(), SIGUSR1);
	else if (strcmp(how, "thread_tgkill") == 0)
		tgkill(getpid(), main_tid, SIGUSR1);
	else
		sigqueue(getpid(), SIGUSR1, v);
	/* On to a later time at once: the receiver's wait must still end at
	 * the send, not wherever the sender (and the world) got to before the
	 * receiver was heard. */
	nanosleep(&d, NULL);
}

static void *sender_thread(void *arg)
{
	(void)arg;
	sigset_t usr1;
	sigemptyset(&usr1);
	sigaddset(&usr1, SIGUSR1);
	pthread_sigmask(SIG_BLOCK, &usr1, NULL); /* the main thread takes it */
	send_it();
	return NULL;
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: signal_time sigqueue|tgkill|thread_tgkill|thread_sigqueue\n");
		return 2;
	}
	how = argv[1];
	sent = mmap(NULL, sizeof *sent, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_sigaction = on_usr1;
	sa.sa_flags = SA_SIGINFO;
	sigaction(SIGUSR1, &sa, NULL);
	main_tid = gettid();
	int threaded = strncmp(how, "thread_", 7) == 0;
	pid_t child = -1;
	pthread_t th;
	t0 = mono();
	if (threaded) {
		pthread_create(&th, NULL, sender_thread, NULL);
	} else if ((child = fork()) == 0) {
		send_it();
		_exit(0);
	}
	struct timespec second = { 1, 0 }, left = { 0, 0 };
	int r = nanosleep(&second, &left);
	int e = r < 0 ? errno : 0;
	long long woke = mono() - t0;
	if (threaded)
		pthread_join(th, NULL);
	else
		waitpid(child, NULL, 0);
	printf("sent=%lld\nhandled=%lld\nvalue=%d\nsleep_errno=%s\nleft=%lld\nwoke=%lld\n", *sent, handled, value,
	       e == EINTR ? "EINTR" : e == 0 ? "none" : "other", left.tv_sec * 1000000000LL + left.tv_nsec, woke);
	return 0;
}
