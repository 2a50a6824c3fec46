/* spin: waits that wait by spinning (docs/DESIGN.md §2, spins in
 * lockstep). Prints key=value lines.
 *   clock N PERIOD_NS   N deadlines PERIOD_NS apart, each waited for by
 *                       reading CLOCK_MONOTONIC until it is there: how long
 *                       in all (span), the most any read past a deadline
 *                       came after it (late), how many reads (reads)
 *   device PATH         a stream sensor opened O_NONBLOCK: a record read,
 *                       then reads until the next (tries, and when it came:
 *                       at, CLOCK_MONOTONIC in ns), then the same by
 *                       zero-timeout polls (poll_tries, poll_at)
 *   alarm MS            a setitimer of MS, spun for on the clock and its
 *                       handler's flag: when the flag was seen (alarm_ns)
 *   thread MS           a thread's MS sleep, spun for on the clock and the
 *                       flag it sets after: when it was seen (thread_ns) */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

static long long mono(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec * 1000000000LL + t.tv_nsec;
}

static int clock_spin(int n, long long period)
{
	long long t0 = mono(), late = 0, reads = 1, now = t0;
	for (int i = 1; i <= n; i++) {
		long long deadline = t0 + i * period;
		while ((now = mono()) < deadline)
			reads++;
		reads++;
		if (now - deadline > late)
			late = now - deadline;
	}
	printf("span=%lld\nlate=%lld\nreads=%lld\n", now - t0, late, reads);
	return 0;
}

/* Reads until a record comes; how many reads found nothing. */
static long long read_until_record(int fd)
{
	char buf[256];
	long long tries = 0;
	for (;;) {
		ssize_t r = read(fd, buf, sizeof buf);
		if (r > 0)
			return tries;
		if (r < 0 && errno != EAGAIN) {
			perror("read");
			exit(1);
		}
		tries++;
	}
}

static void drain(int fd)
{
	char buf[256];
	while (read(fd, buf, sizeof buf) > 0)
		;
}

static int device_spin(const char *path)
{
	int fd = open(path, O_RDONLY | O_NONBLOCK);
	if (fd < 0) {
		perror(path);
		return 1;
	}
	read_until_record(fd);
	drain(fd);
	long long tries = read_until_record(fd);
	printf("tries=%lld\nat=%lld\n", tries, mono());
	drain(fd);
	struct pollfd p = { fd, POLLIN, 0 };
	long long polls = 0;
	while (poll(&p, 1, 0) == 0)
		polls++;
	printf("poll_tries=%lld\npoll_at=%lld\n", polls, mono());
	return 0;
}

static volatile sig_atomic_t flag;

static void on_alarm(int sig)
{
	(void)sig;
	flag = 1;
}

/* Reads the clock until the flag is up: when it was seen, from t0. */
static long long spin_for_flag(long long t0)
{
	long long now;
	while (!(now = mono(), __atomic_load_n(&flag, __ATOMIC_ACQUIRE)))
		;
	return now - t0;
}

static int alarm_spin(long long ms)
{
	signal(SIGALRM, on_alarm);
	long long t0 = mono();
	struct itimerval it = { { 0, 0 }, { 0, ms * 1000 } };
	setitimer(ITIMER_REAL, &it, NULL);
	printf("alarm_ns=%lld\n", spin_for_flag(t0));
	return 0;
}

static void *sleeper(void *arg)
{
	struct timespec d = { 0, *(long long *)arg * 1000000 };
	nanosleep(&d, NULL);
	__atomic_store_n(&flag, 1, __ATOMIC_RELEASE);
	return NULL;
}

static int thread_spin(long long ms)
{
	pthread_t t;
	long long t0 = mono();
	pthread_create(&t, NULL, sleeper, &ms);
	printf("thread_ns=%lld\n", spin_for_flag(t0));
	pthread_join(t, NULL);
	return 0;
}

int main(int argc, char **argv)
{
	if (argc == 3 && !strcmp(argv[1], "alarm"))
		return alarm_spin(atoll(argv[2]));
	if (argc == 3 && !strcmp(argv[1], "thread"))
		return thread_spin(atoll(argv[2]));
	if (argc == 4 && !strcmp(argv[1], "clock"))
		return clock_spin(atoi(argv[2]), atoll(argv[3]));
	if (argc == 3 && !strcmp(argv[1], "device"))
		return device_spin(argv[2]);
	fprintf(stderr, "usage: spin clock N PERIOD_NS | device PATH | alarm MS | thread MS\n");
	return 2;
}
