/* poll_many N: poll and ppoll on the read ends of N pipes (N over 256 is a
 * set tcs re-checks at every step rather than mirrors: tcs-run(1)), each
 * call timed on CLOCK_MONOTONIC. Prints key=value lines:
 *   poll_ret, poll_ns        poll, 10 ms timeout, nothing ready
 *   ppoll_ret, ppoll_ns      ppoll, 10 ms timeout, nothing ready
 *   ready_ret, ready_ns, ready_fds
 *                            poll, 1 s timeout, the last pipe already
 *                            holding a byte: the indexes with revents
 *   woken_ret, woken_fds, write_at, woken_at
 *                            ppoll, no timeout; a forked child writes a
 *                            byte into the last pipe after a 5 ms sleep
 *                            (and ends 20 ms later):
 *                            CLOCK_MONOTONIC (ns) at the child's write
 *                            (read just before it) and at ppoll's return */
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define MS 1000000LL

static long long mono(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec * 1000000000LL + t.tv_nsec;
}

/* The indexes whose revents are set, comma-separated ("none" if none). */
static void print_ready(const char *key, const struct pollfd *p, int n)
{
	printf("%s=", key);
	int any = 0;
	for (int i = 0; i < n; i++)
		if (p[i].revents) {
			printf("%s%d:%s", any ? "," : "", i, p[i].revents == POLLIN ? "POLLIN" : "other");
			any = 1;
		}
	printf("%s\n", any ? "" : "none");
}

int main(int argc, char **argv)
{
	int n = argc == 2 ? atoi(argv[1]) : 0;
	if (n < 1) {
		fprintf(stderr, "usage: poll_many N\n");
		return 2;
	}
	struct pollfd *p = calloc((size_t)n, sizeof *p);
	int *wr = calloc((size_t)n, sizeof *wr);
	for (int i = 0; i < n; i++) {
		int fds[2];
		if (pipe(fds) < 0) {
			perror("pipe");
			return 1;
		}
		p[i].fd = fds[0];
		p[i].events = POLLIN;
		wr[i] = fds[1];
	}

	long long t0 = mono();
	int r = poll(p, (nfds_t)n, 10);
	printf("poll_ret=%d\npoll_ns=%lld\n", r, mono() - t0);

	struct timespec ten = { 0, 10 * MS };
	t0 = mono();
	r = ppoll(p, (nfds_t)n, &ten, NULL);
	printf("ppoll_ret=%d\nppoll_ns=%lld\n", r, mono() - t0);

	(void)!write(wr[n - 1], "x", 1);
	t0 = mono();
	r = poll(p, (nfds_t)n, 1000);
	printf("ready_ret=%d\nready_ns=%lld\n", r, mono() - t0);
	print_ready("ready_fds", p, n);
	char c;
	(void)!read(p[n - 1].fd, &c, 1);

	/* The child's write time, where the parent can read it after. */
	long long *shared = mmap(NULL, sizeof *shared, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	fflush(stdout);
	pid_t child = fork();
	if (child == 0) {
		struct timespec five = { 0, 5 * MS };
		nanosleep(&five, NULL);
		*shared = mono();
		(void)!write(wr[n - 1], "y", 1);
		/* Alive on: its end, which tcs tells its parent of, must not be
		 * what ends the parent's wait. */
		struct timespec twenty = { 0, 20 * MS };
		nanosleep(&twenty, NULL);
		_exit(0);
	}
	r = ppoll(p, (nfds_t)n, NULL, NULL);
	long long woken_at = mono();
	waitpid(child, NULL, 0);
	printf("woken_ret=%d\n", r);
	print_ready("woken_fds", p, n);
	printf("write_at=%lld\nwoken_at=%lld\n", *shared, woken_at);
	return 0;
}
