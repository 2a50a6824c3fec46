/* device_probe CHECK ARGS...: exercises a virtual device the way a driver
 * would, printing key=value lines (times in ns since the probe started, in
 * its own clock; CPU in ns of the process's CPU by the kernel's clock,
 * work.h, not the CPU clock tcs answers) for the process tests to check.
 *   stream PATH N        N blocking reads of a text stream: when each came
 *   nonblock PATH        O_NONBLOCK reads: a record, then reads up to EAGAIN (how many, and
 *                        their time and CPU), then after 1 ms a record
 *   poll PATH            poll(), select() and epoll_wait() with 500 ms timeouts on a drained
 *                        stream: how long each waited, and its CPU
 *   latest PATH          two reads at one instant, one after 5 ms
 *   binary PATH          one record of two little-endian f64
 *   write TORQUE STATE   three commands at one instant (the last is valid), malformed ones
 *                        (EINVAL), saturation; their effect; opens in the wrong direction
 *   batches TEXT BINARY  commands in every shape a write can take (whole records, pieces,
 *                        numbers only strtod reads, a flood with no wait, a last one
 *                        before exit), printing each write's result
 *   termios PATH         tcgetattr/tcsetattr on a device as on a serial port
 *   overflow PATH N      two readers of one stream: one reads N records as they come, the
 *                        other none until then; it then drains what it has without
 *                        blocking, and where each of those records is among the first's
 *                        is printed as runs of consecutive records (from-to,...) */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/select.h>
#include <termios.h>
#include <unistd.h>

#include "work.h"

static long long t0;

static long long since(void)
{
	return clock_ns(CLOCK_MONOTONIC) - t0;
}

static int must_open(const char *path, int flags)
{
	int fd = open(path, flags);
	if (fd < 0) {
		printf("open_errno=%s\n", strerrorname_np(errno));
		exit(1);
	}
	return fd;
}

/* Reads one text record (up to the newline) from a blocking fd. */
static int read_line(int fd, char *buf, size_t len)
{
	size_t n = 0;
	while (n + 1 < len) {
		ssize_t r = read(fd, buf + n, 1);
		if (r <= 0)
			return -1;
		if (buf[n++] == '\n')
			break;
	}
	buf[n] = '\0';
	return (int)n;
}

static void sleep_ms(int ms)
{
	struct timespec ts = { 0, ms * 1000000L };
	nanosleep(&ts, NULL);
}

int main(int argc, char **argv)
{
	t0 = clock_ns(CLOCK_MONOTONIC);
	if (argc < 3)
		return 2;
	const char *check = argv[1], *path = argv[2];
	char line[256];
	if (!strcmp(check, "stream")) {
		int fd = must_open(path, O_RDONLY), n = argc > 3 ? atoi(argv[3]) : 5;
		for (int i = 0; i < n; i++) {
			long long before = kernel_cpu_ns();
			if (read_line(fd, line, sizeof line) < 0)
				return 1;
			long long at = since();
			printf("record%d_at=%lld record%d_cpu0=%lld record%d_cpu=%lld\n", i, at, i, before, i,
			       kernel_cpu_ns());
		}
	} else if (!strcmp(check, "nonblock")) {
		int fd = must_open(path, O_RDONLY | O_NONBLOCK);
		ssize_t a = read(fd, line, sizeof line);
		/* (The CPU read first and last: its window holds the time's.) */
		long long cpu = kernel_cpu_ns(), before = since();
		int more = 0;
		while (more < 100 && read(fd, line, sizeof line) > 0)
			more++;
		int e = errno;
		long long drain = since() - before;
		cpu = kernel_cpu_ns() - cpu;
		sleep_ms(1);
		ssize_t c = read(fd, line, sizeof line);
		printf("first=%d more=%d drain_errno=%s drain_ns=%lld drain_cpu_ns=%lld third=%d at=%lld\n", a > 0, more,
		       strerrorname_np(e), drain, cpu, c > 0, since());
	} else if (!strcmp(check, "poll")) {
		int fd = must_open(path, O_RDONLY | O_NONBLOCK);
		sleep_ms(3);
		while (read(fd, line, sizeof line) > 0) /* drain what is due */
			;
		/* (Each wait's CPU read first and last: its window holds the time's.) */
		long long cpu = kernel_cpu_ns(), before = since();
		struct pollfd p = { fd, POLLIN, 0 };
		int r = poll(&p, 1, 500);
		printf("poll=%d revents_in=%d waited=%lld", r, !!(p.revents & POLLIN), since() - before);
		printf(" poll_cpu=%lld\n", kernel_cpu_ns() - cpu);
		while (read(fd, line, sizeof line) > 0)
			;
		fd_set rs;
		FD_ZERO(&rs);
		FD_SET(fd, &rs);
		struct timeval tv = { 0, 500000 };
		cpu = kernel_cpu_ns(), before = since();
		r = select(fd + 1, &rs, NULL, NULL, &tv);
		printf("select=%d isset=%d waited=%lld", r, FD_ISSET(fd, &rs), since() - before);
		printf(" select_cpu=%lld\n", kernel_cpu_ns() - cpu);
		while (read(fd, line, sizeof line) > 0)
			;
		int ep = epoll_create1(0);
		struct epoll_event ev = { .events = EPOLLIN, .data.fd = fd }, out;
		epoll_ctl(ep, EPOLL_CTL_ADD, fd, &ev);
		cpu = kernel_cpu_ns(), before = since();
		r = epoll_wait(ep, &out, 1, 500);
		printf("epoll_wait=%d fd_ok=%d waited=%lld", r, out.data.fd == fd, since() - before);
		printf(" epoll_wait_cpu=%lld\n", kernel_cpu_ns() - cpu);
	} else if (!strcmp(check, "latest")) {
		int fd = must_open(path, O_RDONLY);
		char a[128] = "", b[128] = "", c[128] = "";
		ssize_t ra = read(fd, a, sizeof a - 1), rb = read(fd, b, sizeof b - 1);
		sleep_ms(5);
		ssize_t rc = read(fd, c, sizeof c - 1);
		printf("reads=%d same_instant_equal=%d later_differs=%d at=%lld\n", ra > 0 && rb > 0 && rc > 0,
		       !strcmp(a, b), strcmp(a, c) != 0, since());
	} else if (!strcmp(check, "binary")) {
		int fd = must_open(path, O_RDONLY);
		double v[2];
		ssize_t r = read(fd, v, sizeof v);
		printf("bytes=%d position=%.6f velocity=%.6f\n", (int)r, v[0], v[1]);
	} else if (!strcmp(check, "write") && argc > 3) {
		int fd = must_open(path, O_WRONLY), st = must_open(argv[3], O_RDONLY);
		/* three at one instant: the last is the one in force */
		int several = write(fd, "-4\n", 3) == 3 && write(fd, "3\n", 2) == 2;
		ssize_t ok = write(fd, "2.0\n", 4);
		errno = 0;
		ssize_t bad1 = write(fd, "abc\n", 4);
		int e1 = errno;
		ssize_t bad2 = write(fd, "1 2\n", 4);
		int e2 = errno;
		sleep_ms(10);
		if (read(st, line, sizeof line) <= 0)
			return 1;
		double pos, vel;
		sscanf(line, "%lf %lf", &pos, &vel);
		ssize_t big = write(fd, "100\n", 4);
		sleep_ms(10);
		double vel2 = vel;
		if (read(st, line, sizeof line) > 0)
			sscanf(line, "%lf %lf", &pos, &vel2);
		printf("several=%d ok=%d bad1=%d bad1_errno=%s bad2=%d bad2_errno=%s velocity_after_10ms=%.17g big=%d "
		       "velocity_gain_next_10ms=%.17g\n",
		       several, (int)ok, (int)bad1, strerrorname_np(e1), (int)bad2, strerrorname_np(e2), vel, (int)big, vel2 - vel);
		int wrong = open(path, O_RDONLY);
		printf("read_open_of_actuator_errno=%s\n", wrong < 0 ? strerrorname_np(errno) : "none");
		wrong = open(path, O_RDWR);
		printf("rdwr_open_of_actuator_errno=%s\n", wrong < 0 ? strerrorname_np(errno) : "none");
		wrong = open(argv[3], O_RDWR);
		printf("rdwr_open_of_sensor_errno=%s\n", wrong < 0 ? strerrorname_np(errno) : "none");
		errno = 0;
		ssize_t rd = read(fd, line, sizeof line);
		printf("read_of_actuator=%d read_of_actuator_errno=%s\n", (int)rd, strerrorname_np(errno));
		errno = 0;
		ssize_t wr = write(st, "1\n", 2);
		printf("write_of_sensor=%d write_of_sensor_errno=%s\n", (int)wr, strerrorname_np(errno));
	} else if (!strcmp(check, "batches") && argc > 3) {
		int fd = must_open(path, O_WRONLY), bin = must_open(argv[3], O_WRONLY);
		double rec[3] = { -1.25, 0.5, 6.0 };
		unsigned char bytes[24];
		memcpy(bytes, rec, sizeof rec);
		/* at 0: a whole record, one in two pieces, one only strtod reads */
		printf("whole=%d", (int)write(fd, "1.5\n", 4));
		printf(" piece1=%d", (int)write(fd, "2.", 2));
		printf(" piece2=%d", (int)write(fd, "5\n", 2));
		printf(" hex=%d", (int)write(fd, "0x1p1\n", 6));
		errno = 0;
		ssize_t overflow = write(fd, "1e999\n", 6);
		printf(" overflow=%d overflow_errno=%s\n", (int)overflow, strerrorname_np(errno));
		sleep_ms(3);
		/* at 3 ms: two records in one write, two binary records, one in pieces */
		printf("two=%d", (int)write(fd, "3 \n4\r\n", 6));
		printf(" bin_two=%d", (int)write(bin, bytes, 16));
		printf(" bin_piece1=%d", (int)write(bin, bytes + 16, 7));
		printf(" bin_piece2=%d\n", (int)write(bin, bytes + 23, 1));
		sleep_ms(2);
		/* at 5 ms: more than a socket buffer's worth without a wait */
		int flooded = 0;
		for (int i = 0; i < 30000; i++)
			flooded += write(fd, "0.250000\n", 9) == 9;
		printf("flooded=%d\n", flooded);
		fflush(stdout);
		/* the last one, and out */
		_exit(write(fd, "4.5\n", 4) == 4 ? 0 : 1);
	} else if (!strcmp(check, "overflow") && argc > 3) {
		int n = atoi(argv[3]), a = must_open(path, O_RDONLY), b = must_open(path, O_RDONLY | O_NONBLOCK);
		char(*seen)[64] = calloc((size_t)n + 1, sizeof *seen);
		for (int i = 0; i < n; i++) {
			if (read_line(a, seen[i], sizeof seen[i]) < 0)
				return 1;
			seen[i][strcspn(seen[i], "\n")] = '\0';
		}
		size_t cap = 1 << 20, len = 0;
		char *held = malloc(cap);
		ssize_t got;
		while ((got = read(b, held + len, cap - len - 1)) > 0)
			if ((len += (size_t)got) + 1 == cap)
				held = realloc(held, cap *= 2);
		int drained_errno = errno;
		held[len] = '\0';
		/* Each of b's records is looked for among a's, from where the last
		 * one was found: runs of consecutive ones are printed. */
		int records = 0, at = 0, run_from = -1, last = -2, missing = 0;
		printf("runs=");
		for (char *rec = strtok(held, "\n"); rec; rec = strtok(NULL, "\n")) {
			records++;
			int i = at;
			while (i < n && strcmp(seen[i], rec) != 0)
				i++;
			if (i == n) {
				missing++;
				continue;
			}
			if (i != last + 1) {
				if (run_from >= 0)
					printf("%d-%d,", run_from, last);
				run_from = i;
			}
			last = at = i;
		}
		if (run_from >= 0)
			printf("%d-%d", run_from, last);
		/* Then it reads on: the next record is the one due next. */
		fcntl(b, F_SETFL, O_RDONLY);
		char next_a[64], next_b[64];
		int next = read_line(b, next_b, sizeof next_b) > 0 && read_line(a, next_a, sizeof next_a) > 0 &&
			   !strcmp(next_a, next_b);
		printf("\nrecords=%d missing=%d drained_errno=%s next_same=%d next_at=%lld\n", records, missing,
		       strerrorname_np(drained_errno), next, since());
	} else if (!strcmp(check, "termios")) {
		int fd = must_open(path, O_RDONLY | O_NOCTTY);
		struct termios t;
		int g = tcgetattr(fd, &t);
		cfmakeraw(&t);
		cfsetspeed(&t, B115200);
		int s = tcsetattr(fd, TCSANOW, &t);
		int fl = tcflush(fd, TCIFLUSH);
		printf("tcgetattr=%d tcsetattr=%d tcflush=%d speed_ok=%d record=%d\n", g, s, fl,
		       cfgetospeed(&t) == B115200, read_line(fd, line, sizeof line) > 0);
	} else {
		return 2;
	}
	return 0;
}
